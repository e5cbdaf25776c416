// Names and units of the eq. (3) terms; see terms.hpp.
#include "kernels/model/terms.hpp"

#include <array>

namespace allanlot::kernels {
namespace {

constexpr std::array<Term, kNumTerms> kTerms = {Term::R, Term::K, Term::B, Term::N, Term::Q};

}  // namespace

std::string_view term_name(Term t) {
  switch (t) {
  case Term::R:
    return "R";
  case Term::K:
    return "K";
  case Term::B:
    return "B";
  case Term::N:
    return "N";
  case Term::Q:
    return "Q";
  }
  throw std::logic_error("terms: bad term");
}

std::optional<Term> parse_term(std::string_view name) {
  for (Term t : kTerms)
    if (term_name(t) == name) return t;
  return std::nullopt;
}

std::span<const Term> all_terms() {
  return kTerms;
}

std::string_view seconds_suffix(Term t) {
  switch (t) {
  case Term::R:
    return "/s";
  case Term::K:
    return "/s^0.5";
  case Term::B:
    return "";
  case Term::N:
    return "*s^0.5";
  case Term::Q:
    return "*s";
  }
  throw std::logic_error("terms: bad term");
}

}  // namespace allanlot::kernels
