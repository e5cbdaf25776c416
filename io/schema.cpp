// The tables of io/schema.hpp. Notes give units and meaning as docs/formats.md "Results file
// layout" and "Lot summary" define them; the order of each table is the order of writing.
#include "io/schema.hpp"

#include <cmath>

namespace allanlot::io::schema {

namespace {
constexpr Kind D = Kind::Dataset;
constexpr Kind A = Kind::Attribute;
}  // namespace

std::span<const Field<RecordingResult>> root_fields() {
  using R = RecordingResult;
  static const Field<R> t[] = {
      {"device_id", A, &R::device_id, "as found in the input", nullptr, Need::Required, true},
      {"source_file", A, &R::source_file, "the input recording", nullptr, Need::Required, true},
      {"tool_version", A, &R::tool_version, "allanlot version", nullptr, Need::Required, true},
      {"created_utc", A, &R::created_utc, "ISO 8601", nullptr, Need::Required, true},
      {"command_line", A, &R::command_line, "as run", nullptr, Need::Required, true},
  };
  return t;
}

std::span<const Field<ChannelResult>> channel_fields() {
  using C = ChannelResult;
  const auto data_known = [](const C& c) { return std::isfinite(c.data_mean); };
  const auto gapped = [](const C& c) { return c.n_gaps > 0; };
  static const Field<C> t[] = {
      {"units", A, &C::units, "the channel's rate units", nullptr, Need::Required, true},
      {"sample_rate_hz", A, &C::sample_rate_hz, "Hz", nullptr, Need::Required, true},
      {"n_samples", A, &C::n_samples, "samples analysed", nullptr, Need::Required, true},
      {"n_gaps", A, &C::n_gaps, "gaps in the samples", nullptr, Need::Required, true},
      {"data_type", A, &C::data_type, "rate or phase", nullptr, Need::Required, true},
      // The gap policy's account, on channels with gaps only: a gap-free file is unchanged.
      {"gap_policy", A, &C::gap_policy, "skip, fill or fill:N", gapped, Need::IfPresent, true},
      {"n_filled", A, &C::n_filled, "missing samples filled", gapped, Need::IfPresent, true},
      {"filled_runs", A, &C::filled_runs, "runs of missing samples filled", gapped, Need::IfPresent,
       true},
      {"gap_runs_left", A, &C::gap_runs_left, "runs left as gaps", gapped, Need::IfPresent, true},
      {"data_max", A, &C::data_max, "largest sample as analysed, channel units", data_known,
       Need::IfPresent, true},
      {"data_min", A, &C::data_min, "smallest sample as analysed, channel units", data_known,
       Need::IfPresent, true},
      {"data_mean", A, &C::data_mean, "mean of the samples as analysed, channel units", data_known,
       Need::IfPresent, true},
      {"status", A, &C::status, "ok or failed: <reason>", nullptr, Need::Required, true},
      {"notes", A, &C::notes, "what was not computed and why",
       [](const C& c) { return !c.notes.empty(); }, Need::IfPresent, true},
  };
  return t;
}

std::span<const Field<kernels::StatResult>> stat_fields() {
  using S = kernels::StatResult;
  const auto ci = [](const S& s) { return s.confidence > 0.0; };
  static const Field<S> t[] = {
      {"m", D, &S::m, "averaging factor"},
      {"tau", D, &S::tau_s, "s"},
      {"dev", D, &S::dev, "deviation, channel units"},
      {"n", D, &S::n, "terms in the estimator's sum"},
      {"edf", D, &S::edf, "equivalent degrees of freedom", ci},
      {"dev_lo", D, &S::dev_lo, "confidence interval, lower bound", ci},
      {"dev_hi", D, &S::dev_hi, "confidence interval, upper bound", ci},
      {"alpha", D, &S::alpha, "identified power-law exponent (i32)", ci},
      {"confidence", A, &S::confidence, "the intervals' confidence level", ci},
  };
  return t;
}

std::span<const Column<TermRecord>> term_columns() {
  using T = TermRecord;
  static const Column<T> t[] = {
      {"term", &T::term, "R, K, B, N or Q", Need::Required, true},
      {"value", &T::value, "channel units and seconds"},
      {"sigma", &T::sigma, "standard uncertainty of value"},
      {"upper", &T::upper, "one-sided 95 % upper bound"},
      {"detected", &T::detected, "u8: 1 significantly non-zero", Need::Required, true},
      {"unit", &T::unit, "unit of value"},
      {"value_datasheet", &T::value_datasheet, "datasheet units", Need::Required, true},
      {"sigma_datasheet", &T::sigma_datasheet, "datasheet units", Need::Required, true},
      // Files of early pre-releases lack it; the lot summary then shows no upper bound.
      {"upper_datasheet", &T::upper_datasheet, "datasheet units", Need::IfPresent, true},
      {"unit_datasheet", &T::unit_datasheet, "e.g. deg/h/sqrt(Hz)", Need::Required, true},
      {"value_datasheet_alt", &T::value_datasheet_alt, "secondary datasheet form"},
      {"unit_datasheet_alt", &T::unit_datasheet_alt, "its unit; empty when none"},
  };
  return t;
}

std::span<const Field<FitRecord>> fit_fields() {
  using F = FitRecord;
  // fit/ carries the model on the oadev taus, psd_fit/ on the PSD frequencies and the
  // comparison with fit/ (agree >= 0).
  const auto on_taus = [](const F& f) { return !f.tau.empty() || f.f.empty(); };
  const auto on_freqs = [](const F& f) { return !f.f.empty(); };
  const auto compared = [](const F& f) { return f.agree >= 0; };
  const auto modelled = [](const F& f) { return !f.model.empty(); };
  static const Field<F> t[] = {
      {"tau", D, &F::tau, "s", on_taus},
      {"adev_model", D, &F::adev_model, "the fitted model's deviation", on_taus},
      {"f", D, &F::f, "Hz, log-binned", on_freqs},
      {"psd_model", D, &F::psd_model, "u^2/Hz, expected Welch value", on_freqs},
      {"z_vs_fit", D, &F::z_vs_fit, "z per term against fit/", compared},
      {"agrees_with_fit", A, &F::agree, "i64: 1 agree, 0 not", compared, Need::IfPresent, true},
      {"max_abs_z", A, &F::max_abs_z, "largest |z|", compared, Need::IfPresent, true},
      {"worst_term", A, &F::worst_term, "where it is reached", compared},
      {"method", A, &F::method, "how it was fitted"},
      {"status", A, &F::status, "ok, poor fit, no data, rank deficient, no convergence", nullptr,
       Need::IfPresent, true},
      {"rank", A, &F::rank, "i64: independent regressors"},
      {"chi2_dof", A, &F::chi2_dof, "reduced chi-square", nullptr, Need::IfPresent, true},
      // fit/ only (written with its taus); absent from files of versions without the filter.
      {"lowpass", A, &F::lowpass, "the sensor's filter: auto, auto-unused, option or none", on_taus,
       Need::IfPresent, true},
      {"lowpass_cutoff_hz", A, &F::lowpass_cutoff_hz, "Hz, first order; NaN otherwise", on_taus,
       Need::IfPresent, true},
      {"lowpass_taps", A, &F::lowpass_taps, "moving average, samples; NaN otherwise", on_taus,
       Need::IfPresent, true},
      {"lowpass_delta_ic", A, &F::lowpass_delta_ic, "auto test's criterion, > 0 named; NaN",
       on_taus, Need::IfPresent},
      {"first_tau_fitted", A, &F::first_tau_fitted, "s, the first tau the fit used", on_taus,
       Need::IfPresent, true},
      {"taus_fitted", A, &F::taus_fitted, "i64: taus the fit used", on_taus, Need::IfPresent},
      {"chi2_dof_all_taus", A, &F::chi2_dof_all_taus, "the fit over every tau", on_taus,
       Need::IfPresent, true},
      // fit/ of a poor fit that analyze modelled (docs/fit-and-psd.md); absent otherwise.
      {"model", A, &F::model, "eq. (3) + the effects named; the terms are this model's", modelled,
       Need::IfPresent, true},
      {"model_gap", A, &F::model_gap, "the model's gap against the measured curve", modelled,
       Need::IfPresent},
      {"model_gap_p95", A, &F::model_gap_p95, "p95 of its replicas' gaps", modelled,
       Need::IfPresent},
      {"model_replicas", A, &F::model_replicas, "i64: Monte Carlo replicas", modelled,
       Need::IfPresent},
      {"model_within_noise", A, &F::model_within_noise, "i64: 1 within noise, 0 not", modelled,
       Need::IfPresent, true},
  };
  return t;
}

std::span<const Column<ReadoutRecord>> readout_columns() {
  using X = ReadoutRecord;
  static const Column<X> t[] = {
      // Marked `summary`: the lot summary's read-out columns come from them.
      {"name", &X::name, "N_1s, bias_instability, K_3s", Need::Required, true},
      {"valid", &X::valid, "u8", Need::Required, true},
      {"value", &X::value, "channel units"},
      {"sigma", &X::sigma, "channel units"},
      {"tau", &X::tau_s, "s", Need::Required, true},
      {"model", &X::model, "the fit's value there"},
      {"value_datasheet", &X::value_datasheet, "datasheet units", Need::Required, true},
      {"sigma_datasheet", &X::sigma_datasheet, "datasheet units", Need::Required, true},
      {"unit_datasheet", &X::unit_datasheet, "e.g. deg/h", Need::Required, true},
      {"value_datasheet_alt", &X::value_datasheet_alt, "ARW/VRW form of N; NaN otherwise",
       Need::IfPresent, true},
      {"sigma_datasheet_alt", &X::sigma_datasheet_alt, "its uncertainty", Need::IfPresent, true},
      {"unit_datasheet_alt", &X::unit_datasheet_alt, "e.g. deg/sqrt(h); empty otherwise",
       Need::IfPresent, true},
  };
  return t;
}

std::span<const Column<EffectRecord>> effect_columns() {
  using E = EffectRecord;
  static const Column<E> t[] = {
      {"effect_index", &E::effect_index, "which named effect, 0, 1, ...", Need::Required, true},
      {"effect", &E::effect, "lowpass, resonance, markov, sinusoid, step, ...", Need::Required,
       true},
      {"parameter", &E::parameter, "model file key: frequency_hz, q, sigma, ...", Need::Required,
       true},
      {"value", &E::value, "channel units, seconds, Hz", Need::Required, true},
      {"sigma", &E::sigma, "1-sigma; NaN when not estimable", Need::Required, true},
      {"bound", &E::bound, "0 estimate; -1, +1 at the search's lower, upper end", Need::Required,
       true},
  };
  return t;
}

std::span<const Field<PsdRecord>> psd_fields() {
  using P = PsdRecord;
  static const Field<P> t[] = {
      {"f", D, &P::f, "Hz, log-binned"},
      {"psd", D, &P::psd, "u^2/Hz, one-sided"},
      {"edf", D, &P::edf, "chi-square dof of each value"},
      {"n_avg", D, &P::n_avg, "Welch bins averaged"},
      {"method", A, &P::method, "e.g. welch hann 50% overlap"},
      {"convention", A, &P::convention, "one-sided"},
  };
  return t;
}

std::span<const Field<CrosscheckRecord>> crosscheck_fields() {
  using X = CrosscheckRecord;
  static const Field<X> t[] = {
      {"tau", D, &X::tau, "s"},
      {"avar_time", D, &X::avar_time, "overlapping Allan variance"},
      {"avar_psd", D, &X::avar_psd, "eq. (2) on the measured PSD"},
      {"ratio", D, &X::ratio, "avar_psd / avar_time"},
      {"valid", D, &X::valid, "u8: 1 where eq. (2) is trustworthy"},
      {"max_abs_log10_ratio", A, &X::max_abs_log10_ratio, "over the valid taus", nullptr,
       Need::IfPresent, true},
      {"valid_tau_range", A, &X::valid_tau_range, "{min, max} of the valid taus, s"},
      {"worst_tau", A, &X::worst_tau, "s, where |log10 ratio| peaks", nullptr, Need::IfPresent,
       true},
  };
  return t;
}

std::span<const Field<DiagnosisRecord>> diagnosis_fields() {
  using G = DiagnosisRecord;
  // docs/diagnose.md "Output". Every dataset is read when present: the report shows whatever
  // part of a diagnosis a file holds.
  constexpr Need opt = Need::IfPresent;
  static const Field<G> t[] = {
      {"m", D, &G::m, "averaging factor, per tau", nullptr, opt},
      {"tau", D, &G::tau, "s", nullptr, opt},
      {"avar_measured", D, &G::avar_measured, "Allan variance", nullptr, opt},
      {"edf", D, &G::edf, "equivalent degrees of freedom", nullptr, opt},
      {"avar_model_before", D, &G::avar_model_before, "Allan variance", nullptr, opt},
      {"avar_model_after", D, &G::avar_model_after, "Allan variance", nullptr, opt},
      {"mc_before_lo", D, &G::mc_before_lo, "Monte Carlo 5 %, avar", nullptr, opt},
      {"mc_before_hi", D, &G::mc_before_hi, "Monte Carlo 95 %, avar", nullptr, opt},
      {"mc_after_lo", D, &G::mc_after_lo, "Monte Carlo 5 %, avar", nullptr, opt},
      {"mc_after_hi", D, &G::mc_after_hi, "Monte Carlo 95 %, avar", nullptr, opt},
      {"z_before", D, &G::z_before, "per tau", nullptr, opt},
      {"z_after", D, &G::z_after, "per tau", nullptr, opt},
      {"significant_before", D, &G::significant_before, "u8 per tau", nullptr, opt},
      {"significant_after", D, &G::significant_after, "u8 per tau", nullptr, opt},
      {"effect", D, &G::effect, "per iteration: the effect added", nullptr, opt},
      {"parameters", D, &G::parameters_json, "per iteration: JSON", nullptr, opt},
      {"gap_iteration_before", D, &G::gap_before, "per iteration", nullptr, opt},
      {"gap_iteration_after", D, &G::gap_after, "per iteration", nullptr, opt},
      {"delta_ic", D, &G::delta_ic, "per iteration", nullptr, opt},
  };
  return t;
}

std::span<const Field<kernels::QualityReport>> quality_fields() {
  using Q = kernels::QualityReport;
  // docs/quality.md. Every field is an attribute (read when present); positions are sample
  // indices, -1 when there is none. `summary`: what the lot summary's quality columns need.
  constexpr Need opt = Need::IfPresent;
  static const Field<Q> t[] = {
      {"flags", A, &Q::flags, "raised: gaps;time_stamps;saturation;stuck;spikes", nullptr, opt,
       true},
      {"n_samples", A, &Q::n_samples, "samples screened", nullptr, opt},
      {"n_missing", A, &Q::n_missing, "missing samples (NaN)", nullptr, opt, true},
      {"n_gap_runs", A, &Q::n_gap_runs, "runs of missing samples", nullptr, opt, true},
      {"first_gap", A, &Q::first_gap, "start of the first", nullptr, opt},
      {"n_duplicate_times", A, &Q::n_duplicate_times, "time stamps equal to the previous", nullptr,
       opt, true},
      {"first_duplicate_time", A, &Q::first_duplicate_time, "sample index", nullptr, opt},
      {"n_decreasing_times", A, &Q::n_decreasing_times, "time stamps below the previous", nullptr,
       opt, true},
      {"first_decreasing_time", A, &Q::first_decreasing_time, "sample index", nullptr, opt},
      {"n_saturated_runs", A, &Q::n_saturated_runs, "runs at a limit or piled-up extreme", nullptr,
       opt, true},
      {"n_saturated_samples", A, &Q::n_saturated_samples, "samples in them", nullptr, opt, true},
      {"first_saturated", A, &Q::first_saturated, "start of the first", nullptr, opt},
      {"longest_run", A, &Q::longest_run, "longest run of identical samples", nullptr, opt, true},
      {"longest_run_start", A, &Q::longest_run_start, "its start", nullptr, opt},
      {"stuck_run", A, &Q::stuck_run, "shortest run length counted as stuck", nullptr, opt},
      {"n_stuck_runs", A, &Q::n_stuck_runs, "runs at least that long", nullptr, opt, true},
      {"first_stuck", A, &Q::first_stuck, "start of the first", nullptr, opt},
      {"p_equal", A, &Q::p_equal, "P(sample equals its predecessor)", nullptr, opt},
      {"p_continue", A, &Q::p_continue, "P(... again, after an equal pair)", nullptr, opt},
      {"n_spikes", A, &Q::n_spikes, "samples beyond the spike threshold", nullptr, opt, true},
      {"first_spike", A, &Q::first_spike, "index of the first", nullptr, opt},
      {"max_spike_sigmas", A, &Q::max_spike_sigmas, "largest |x - running median| / sigma", nullptr,
       opt, true},
      {"spike_window", A, &Q::spike_window, "running-median window, samples", nullptr, opt},
  };
  return t;
}

// A clock's power-law model (docs/clocks.md, docs/formats.md "Results file layout").
std::span<const Field<PowerLawRecord>> powerlaw_fields() {
  using P = PowerLawRecord;
  static const Field<P> t[] = {
      {"tau", D, &P::tau, "s, the OADEV taus fitted"},
      {"adev_model", D, &P::adev_model, "the model's Allan deviation there"},
      {"mdev_tau", D, &P::mdev_tau, "s, the MDEV taus fitted"},
      {"mdev_model", D, &P::mdev_model, "the model's modified Allan deviation there"},
      {"method", A, &P::method, "how it was fitted"},
      {"status", A, &P::status, "ok, no_data, rank_deficient, no_convergence", nullptr,
       Need::IfPresent, true},
  };
  return t;
}

std::span<const Column<PowerLawLevelRecord>> powerlaw_columns() {
  using L = PowerLawLevelRecord;
  static const Column<L> t[] = {
      {"alpha", &L::alpha, "i64: S_y ~ f^alpha, 2 .. -2", Need::Required, true},
      {"name", &L::name, "white PM, flicker PM, white FM, flicker FM, random-walk FM",
       Need::Required, true},
      {"h", &L::h, "h_alpha, Hz^(-1-alpha)", Need::Required, true},
      {"h_sigma", &L::h_sigma, "standard uncertainty of h", Need::Required, true},
      {"h_upper", &L::h_upper, "one-sided 95 % upper bound", Need::Required, true},
      {"detected", &L::detected, "u8: 1 significantly above zero", Need::Required, true},
  };
  return t;
}

namespace {

std::string h_detected_csv(const SummaryRow& r, std::size_t i) {
  return std::isnan(r.h[i]) ? "" : r.h_detected[i] ? "1" : "0";
}

std::string detected_csv(const SummaryRow& r, std::size_t i) {
  return std::isnan(r.value[i]) ? "" : r.detected[i] ? "1" : "0";
}

std::string agree_csv(const SummaryRow& r, std::size_t) {
  return r.fits_agree < 0 ? "" : std::to_string(r.fits_agree);
}

// A quality count is empty in the CSV for a row that was not screened (no quality/ group), so
// that it never reads as a clean 0.
template <std::int64_t SummaryRow::*M>
std::string quality_count(const SummaryRow& r, std::size_t) {
  return r.quality.empty() ? "" : std::to_string(r.*M);
}

}  // namespace

std::span<const RowColumn<SummaryRow>> summary_columns() {
  using S = SummaryRow;
  // Columns added after the first release go last, so that readers by position keep working.
  static const RowColumn<S> t[] = {
      {"device_id", &S::device_id, "as found in the input"},
      {"channel", &S::channel, "channel path; empty for a failed input"},
      {"units", &S::units, "the channel's units"},
      {"n_samples", &S::n_samples, "samples analysed"},
      {"status", &S::status, "ok or failed: <reason>"},
      {"source_file", &S::source_file, "the input recording"},
      {"", &S::value, "fitted term, datasheet units; NaN without a fit", 1},
      {"_sigma", &S::sigma, "its standard uncertainty", 1},
      {"_unit", &S::unit, "its datasheet unit", 1},
      {"_detected", &S::detected, "u8: 1 detected; empty in the CSV without a value", 1,
       detected_csv},
      {"chi2_dof", &S::chi2_dof, "the fit's reduced chi-square"},
      {"fit_status", &S::fit_status,
       "ok, poor fit (chi2/dof = X), no data, rank deficient, no convergence; empty"},
      {"max_abs_log10_ratio", &S::max_abs_log10_ratio, "the eq. (2) cross-check"},
      {"crosscheck_worst_tau", &S::crosscheck_worst_tau, "s"},
      {"fits_agree", &S::fits_agree, "i8: 1 agree, 0 not, -1 (CSV empty) not compared", 0,
       agree_csv},
      {"fits_max_abs_z", &S::fits_max_abs_z, "largest |z| of the comparison"},
      {"_upper", &S::upper, "one-sided 95 % upper bound, datasheet units", 2},
      {"spec_status", &S::spec_status, "pass, fail, undecided, no spec, no data; empty"},
      {"spec_detail", &S::spec_detail, "the terms that decided it"},
      {"outlier", &S::outlier, "u8: 1 a term is a lot outlier"},
      {"outlier_terms", &S::outlier_terms, "which, with their modified z-scores"},
      {"_spec_status", &S::spec_term_status, "pass, fail, undecided; empty", 3},
      {"readout_N", &S::readout_n, "N read at 1 s (IEEE 952), datasheet units"},
      {"readout_N_sigma", &S::readout_n_sigma, "its uncertainty"},
      {"readout_N_unit", &S::readout_n_unit, "e.g. deg/h/sqrt(Hz)"},
      {"readout_N_alt", &S::readout_n_alt, "the same as ARW or VRW"},
      {"readout_N_alt_sigma", &S::readout_n_alt_sigma, "its uncertainty"},
      {"readout_N_alt_unit", &S::readout_n_alt_unit, "deg/sqrt(h) or m/s/sqrt(h)"},
      {"readout_B", &S::readout_b, "bias instability: min deviation / 0.664"},
      {"readout_B_sigma", &S::readout_b_sigma, "its uncertainty"},
      {"readout_B_unit", &S::readout_b_unit, "e.g. deg/h"},
      {"readout_B_tau", &S::readout_b_tau, "s, the tau of the minimum"},
      {"readout_K", &S::readout_k, "K read at 3 s on the +1/2 line touching the curve"},
      {"readout_K_sigma", &S::readout_k_sigma, "its uncertainty"},
      {"readout_K_unit", &S::readout_k_unit, "e.g. deg/h/sqrt(h)"},
      {"readout_K_tau", &S::readout_k_tau, "s, where the line touches"},
      {"readouts_valid", &S::readouts_valid,
       "the read-outs whose term the fit detects, e.g. 'N B'; the others read a branch the "
       "curve may not have"},
      {"quality", &S::quality, "flags raised, ok when none; empty when not screened"},
      {"n_missing", &S::n_missing, "missing samples", 0, quality_count<&S::n_missing>},
      {"n_gap_runs", &S::n_gap_runs, "runs of missing samples", 0, quality_count<&S::n_gap_runs>},
      {"n_time_errors", &S::n_time_errors, "duplicate or decreasing time stamps", 0,
       quality_count<&S::n_time_errors>},
      {"n_saturated", &S::n_saturated, "samples in saturated runs", 0,
       quality_count<&S::n_saturated>},
      {"longest_run", &S::longest_run, "longest run of identical samples", 0,
       quality_count<&S::longest_run>},
      {"n_stuck", &S::n_stuck, "runs long enough to be stuck output", 0,
       quality_count<&S::n_stuck>},
      {"n_spikes", &S::n_spikes, "samples beyond 10 robust sigmas", 0, quality_count<&S::n_spikes>},
      {"max_spike_sigmas", &S::max_spike_sigmas, "largest distance from the running median"},
      {"unit_spec_status", &S::unit_spec_status,
       "the unit's verdict: pass only when every channel with a rule passes; empty"},
      {"unit_spec_detail", &S::unit_spec_detail, "the channels behind it, with their terms"},
      {"lowpass", &S::lowpass,
       "the fit's sensor filter: auto, auto-unused, option, none; empty without a fit"},
      {"lowpass_cutoff_hz", &S::lowpass_cutoff_hz, "first-order cutoff, Hz; NaN for a boxcar"},
      {"lowpass_taps", &S::lowpass_taps, "moving-average length, samples; NaN for first order"},
      {"first_tau_fitted", &S::first_tau_fitted, "s, the first tau the fit used"},
      {"chi2_dof_all_taus", &S::chi2_dof_all_taus, "the fit over every tau, beside chi2_dof"},
      // A clock's power-law levels (docs/clocks.md): h2 .. hm2, each with _sigma, _upper and
      // _detected.
      {"", &S::h, "power-law level h_alpha, Hz^(-1-alpha); NaN without the model", 4, nullptr,
       &kLevelNames},
      {"_sigma", &S::h_sigma, "its standard uncertainty", 4, nullptr, &kLevelNames},
      {"_upper", &S::h_upper, "one-sided 95 % upper bound", 4, nullptr, &kLevelNames},
      {"_detected", &S::h_detected, "u8: 1 detected; empty in the CSV without a value", 4,
       h_detected_csv, &kLevelNames},
  };
  return t;
}

std::span<const RowColumn<StatisticsRow>> statistics_columns() {
  using S = StatisticsRow;
  static const RowColumn<S> t[] = {
      {"channel", &S::channel, "channel path"},
      {"term", &S::term, "R, K, B, N or Q"},
      {"unit", &S::unit, "datasheet unit of every value in the row"},
      {"n", &S::n, "units with a value"},
      {"n_detected", &S::n_detected, "of those, units where the term is detected"},
      {"n_outliers", &S::n_outliers, "units flagged as outliers on this term"},
      {"median", &S::median, ""},
      {"spread", &S::spread, "1.4826 * MAD"},
      {"p5", &S::p5, ""},
      {"p25", &S::p25, ""},
      {"p75", &S::p75, ""},
      {"p95", &S::p95, ""},
      {"min", &S::min, ""},
      {"max", &S::max, ""},
  };
  return t;
}

}  // namespace allanlot::io::schema
