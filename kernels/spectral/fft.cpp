// The FFTW wrapper; see fft.hpp.
#include "kernels/spectral/fft.hpp"

#include <stdexcept>
#include <string>
#include <utility>

namespace allanlot::kernels {

namespace detail {
std::mutex& fftw_planner_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace detail

namespace fft {
namespace {

fftw_plan checked(fftw_plan p, const char* who) {
  if (!p) throw std::runtime_error(std::string(who) + ": FFTW planning failed");
  return p;
}

}  // namespace

Plan Plan::r2c(int n, double* in, fftw_complex* out, const char* who) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  return Plan(checked(fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE), who));
}

Plan Plan::c2r(int n, fftw_complex* in, double* out, const char* who) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  return Plan(checked(fftw_plan_dft_c2r_1d(n, in, out, FFTW_ESTIMATE), who));
}

Plan Plan::r2c_batch(int n, int howmany, double* in, fftw_complex* out, const char* who) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  return Plan(checked(fftw_plan_many_dft_r2c(1, &n, howmany, in, nullptr, 1, n, out, nullptr, 1,
                                             n / 2 + 1, FFTW_ESTIMATE),
                      who));
}

Plan::Plan(Plan&& other) noexcept : plan_(std::exchange(other.plan_, nullptr)) {}

Plan& Plan::operator=(Plan&& other) noexcept {
  if (this != &other) {
    Plan old(std::exchange(plan_, std::exchange(other.plan_, nullptr)));
  }
  return *this;
}

Plan::~Plan() {
  if (!plan_) return;
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  fftw_destroy_plan(plan_);
}

void Plan::execute() const {
  fftw_execute(plan_);
}

void Plan::execute_r2c(double* in, fftw_complex* out) const {
  fftw_execute_dft_r2c(plan_, in, out);
}

}  // namespace fft
}  // namespace allanlot::kernels
