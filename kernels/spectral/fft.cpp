// The FFTW wrapper; see fft.hpp.
#include "kernels/spectral/fft.hpp"

#include "kernels/common/large_vector.hpp"

#include <algorithm>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

namespace allanlot::kernels {

// The stored wisdom (fft_wisdom.txt), compiled in by CMake (fft_wisdom.cpp.in).
extern const char* const kStoredFftWisdom;

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

void* allocate_aligned(std::size_t bytes) {
  if (bytes >= kHugeBytes) return allocate_huge(bytes);  // as LargeVector's
  const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + 63) / 64 * 64;
  void* p = std::aligned_alloc(64, rounded);
  if (!p) throw std::bad_alloc();
  return p;
}

Plan Plan::r2c(int n, double* in, fftw_complex* out, const char* who) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  return Plan(checked(fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE), who));
}

Plan Plan::c2r(int n, fftw_complex* in, double* out, const char* who) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  return Plan(checked(fftw_plan_dft_c2r_1d(n, in, out, FFTW_ESTIMATE), who));
}

Plan Plan::r2c_stored(int n, double* in, fftw_complex* out, const char* who, bool* from_wisdom) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  fftw_plan p = nullptr;
  if (fftw_import_wisdom_from_string(kStoredFftWisdom) != 0)
    p = fftw_plan_dft_r2c_1d(n, in, out, FFTW_MEASURE | FFTW_WISDOM_ONLY);
  fftw_forget_wisdom();
  if (from_wisdom) *from_wisdom = p != nullptr;
  if (!p) p = fftw_plan_dft_r2c_1d(n, in, out, FFTW_ESTIMATE);
  return Plan(checked(p, who));
}

std::string measure_r2c_wisdom(const std::vector<int>& lengths) {
  std::lock_guard<std::mutex> lock(detail::fftw_planner_mutex());
  fftw_forget_wisdom();
  for (const int n : lengths) {
    const Buffer<double> in = alloc<double>(static_cast<std::size_t>(n));
    const Buffer<fftw_complex> out = alloc<fftw_complex>(static_cast<std::size_t>(n / 2 + 1));
    fftw_plan p = fftw_plan_dft_r2c_1d(n, in.get(), out.get(), FFTW_MEASURE);
    if (!p)
      throw std::runtime_error("measure_r2c_wisdom: FFTW planning failed for n = " +
                               std::to_string(n));
    fftw_destroy_plan(p);
  }
  char* text = fftw_export_wisdom_to_string();
  fftw_forget_wisdom();
  if (!text) throw std::runtime_error("measure_r2c_wisdom: FFTW exported no wisdom");
  std::string wisdom(text);
  std::free(text);
  return wisdom;
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
