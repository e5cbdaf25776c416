// Model file parsing and writing; the rules are listed in model.hpp.
#include "src/lot/model.hpp"

#include "kernels/model/units.hpp"
#include "kernels/powerlaw/names.hpp"
#include "kernels/powerlaw/theory.hpp"
#include "kernels/simulate/rng.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace allanlot::model {

namespace {

using Json = nlohmann::ordered_json;  // ordered: channels keep the file's order
namespace units = kernels::units;

[[noreturn]] void fail(const std::string& source, const std::string& path,
                       const std::string& reason) {
  throw Error(source + ": " + (path.empty() ? std::string() : path + ": ") + reason);
}

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string type_name(const Json& j) {
  return j.type_name();
}

double number(const Json& j, const std::string& source, const std::string& path) {
  if (!j.is_number()) fail(source, path, "must be a number, not " + type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(source, path, "must be finite");
  return v;
}

double nonneg(const Json& j, const std::string& source, const std::string& path) {
  const double v = number(j, source, path);
  if (v < 0) fail(source, path, "must be >= 0, got " + j.dump());
  return v;
}

double positive(const Json& j, const std::string& source, const std::string& path) {
  const double v = number(j, source, path);
  if (v <= 0) fail(source, path, "must be > 0, got " + j.dump());
  return v;
}

const Json& object(const Json& j, const std::string& source, const std::string& path) {
  if (!j.is_object()) fail(source, path, "must be an object, not " + type_name(j));
  return j;
}

void only_keys(const Json& j, std::initializer_list<const char*> allowed, const std::string& source,
               const std::string& path) {
  for (const auto& [key, value] : j.items()) {
    bool ok = false;
    for (const char* a : allowed)
      ok = ok || key == a;
    if (!ok) fail(source, join(path, key), "unknown key");
  }
}

const Json& required(const Json& j, const char* key, const std::string& source,
                     const std::string& path) {
  const auto it = j.find(key);
  if (it == j.end()) fail(source, join(path, key), "missing");
  return *it;
}

double* term_field(kernels::NoiseTerms& t, units::Term term) {
  switch (term) {
  case units::Term::R:
    return &t.R;
  case units::Term::K:
    return &t.K;
  case units::Term::B:
    return &t.B;
  case units::Term::N:
    return &t.N;
  case units::Term::Q:
    return &t.Q;
  }
  return nullptr;
}

double term_value(const kernels::NoiseTerms& t, units::Term term) {
  switch (term) {
  case units::Term::R:
    return t.R;
  case units::Term::K:
    return t.K;
  case units::Term::B:
    return t.B;
  case units::Term::N:
    return t.N;
  case units::Term::Q:
    return t.Q;
  }
  return 0;
}

kernels::NoiseTerms parse_terms(const Json& j, const std::string& source, const std::string& path) {
  object(j, source, path);
  kernels::NoiseTerms t;
  for (const auto& [key, value] : j.items()) {
    const auto term = units::parse_term(key);
    if (!term) fail(source, join(path, key), "unknown key");
    *term_field(t, *term) = nonneg(value, source, join(path, key));
  }
  return t;
}

bool valid_name(std::string_view name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
      return false;
  return true;
}

std::string number_text(double v) {
  return Json(v).dump();
}

double keyed_number(const Json& j, kernels::KeyRule rule, const std::string& source,
                    const std::string& path) {
  switch (rule) {
  case kernels::KeyRule::NonNegative:
    return nonneg(j, source, path);
  case kernels::KeyRule::Positive:
    return positive(j, source, path);
  case kernels::KeyRule::Finite:
    break;
  }
  return number(j, source, path);
}

// Only "type" and effect E's own keys (kernels/model/effects/).
template <class E>
void only_effect_keys(const Json& e, const std::string& source, const std::string& at) {
  for (const auto& item : e.items()) {
    const std::string& key = item.key();
    const auto& keys = kernels::EffectTraits<E>::keys;
    if (key != "type" &&
        std::none_of(keys.begin(), keys.end(), [&](const auto& k) { return key == k.name; }))
      fail(source, join(at, key), "unknown key");
  }
}

// An effect of type E read by its keys' rules, then its own checks.
template <class E>
E parse_effect(const Json& e, double rate_hz, const std::string& source, const std::string& at) {
  only_effect_keys<E>(e, source, at);
  E x;
  for (const auto& k : kernels::EffectTraits<E>::keys) {
    const std::string key(k.name);
    const bool given = e.contains(key);
    if (k.presence == kernels::Presence::When && !k.needed(x)) continue;
    if (k.presence == kernels::Presence::Required || k.presence == kernels::Presence::When)
      x.*k.field =
          keyed_number(required(e, key.c_str(), source, at), k.rule, source, join(at, key));
    else if (given)
      x.*k.field = keyed_number(e[key], k.rule, source, join(at, key));
  }
  if (const auto problem = kernels::EffectTraits<E>::check(x, rate_hz, number_text))
    fail(source, problem->key.empty() ? at : join(at, problem->key), problem->reason);
  return x;
}

// The sensor's filter: exactly one of its two keys (first order or moving average), at most one
// per channel.
void parse_lowpass(const Json& e, double rate_hz, Channel& ch, const std::string& source,
                   const std::string& at) {
  using Traits = kernels::EffectTraits<kernels::Lowpass>;
  only_effect_keys<kernels::Lowpass>(e, source, at);
  if (ch.lowpass.active()) fail(source, at, "at most one " + std::string(Traits::name) + " effect");
  const std::string cutoff(Traits::keys[0].name), taps(Traits::keys[1].name);
  if (e.contains(cutoff) == e.contains(taps))
    fail(source, at,
         "a " + std::string(Traits::name) + " has exactly one of " + cutoff + " and " + taps);
  kernels::Lowpass lp;
  for (const auto& k : Traits::keys) {
    const std::string key(k.name);
    if (e.contains(key)) lp.*k.field = keyed_number(e[key], k.rule, source, join(at, key));
  }
  if (const auto problem = Traits::check(lp, rate_hz, number_text))
    fail(source, join(at, problem->key), problem->reason);
  ch.lowpass = lp;
}

void parse_effects(const Json& j, double rate_hz, Channel& ch, const std::string& source,
                   const std::string& path) {
  if (!j.is_array()) fail(source, path, "must be an array, not " + type_name(j));
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    const Json& e = object(j[i], source, at);
    const Json& type = required(e, "type", source, at);
    if (!type.is_string()) fail(source, join(at, "type"), "must be a string");
    const auto kind = type.get<std::string>();
    bool known = false;
    kernels::for_each_effect_list(ch, [&](auto& list) {
      using E = typename std::decay_t<decltype(list)>::value_type;
      using Traits = kernels::EffectTraits<E>;
      if (known || kind != Traits::name) return;
      known = true;
      const E x = parse_effect<E>(e, rate_hz, source, at);
      if constexpr (Traits::max_count > 0)
        if (list.size() >= Traits::max_count)
          fail(source, at,
               "at most " + std::to_string(Traits::max_count) + " " + kind + " effects");
      list.push_back(x);
    });
    if (!known && kind == kernels::EffectTraits<kernels::Lowpass>::name) {
      parse_lowpass(e, rate_hz, ch, source, at);
      known = true;
    }
    if (!known)
      fail(source, join(at, "type"),
           "unknown effect type '" + kind + "' (expected " + kernels::effect_type_list() + ")");
  }
}

// "powerlaw" and "output" of a clock's channel (docs/clocks.md "Simulating clocks").
void parse_clock_keys(const Json& j, Channel& ch, const std::string& source,
                      const std::string& path) {
  if (j.contains("powerlaw")) {
    const std::string pp = join(path, "powerlaw");
    const Json& levels = object(j["powerlaw"], source, pp);
    for (const auto& item : levels.items()) {
      const std::string& key = item.key();
      const Json& value = item.value();
      const auto& keys = kernels::powerlaw::kLevelKeys;
      const auto it =
          std::find_if(keys.begin(), keys.end(), [&](const char* k) { return key == k; });
      if (it == keys.end()) fail(source, join(pp, key), "unknown key (h2, h1, h0, hm1 or hm2)");
      ch.powerlaw[static_cast<std::size_t>(it - keys.begin())] =
          nonneg(value, source, join(pp, key));
    }
  }
  if (j.contains("output")) {
    const Json& o = j["output"];
    if (!o.is_string() || (o.get<std::string>() != "frequency" && o.get<std::string>() != "phase"))
      fail(source, join(path, "output"), "must be \"frequency\" or \"phase\"");
    ch.phase_output = o.get<std::string>() == "phase";
  }
}

// The keys of a channel object, shared by the single-channel form's top level.
void parse_channel_body(const Json& j, double rate_hz, Channel& ch, const std::string& source,
                        const std::string& path) {
  const Json& u = required(j, "units", source, path);
  if (!u.is_string() || u.get<std::string>().empty())
    fail(source, join(path, "units"), "must be a non-empty string");
  ch.units = u.get<std::string>();
  // "dps" is deg/s (the one vocabulary, kernels/model/units.hpp); units that scale (ppb, ns)
  // stay as written, as the terms are given in them, and are scaled when a recording is read.
  if (const auto known = units::parse_channel_units(ch.units); known && known->scale == 1)
    ch.units = known->canonical;
  if (j.contains("terms")) ch.terms = parse_terms(j["terms"], source, join(path, "terms"));
  if (j.contains("effects"))
    parse_effects(j["effects"], rate_hz, ch, source, join(path, "effects"));
  if (j.contains("offset")) ch.offset = number(j["offset"], source, join(path, "offset"));
  if (j.contains("quantum")) {
    ch.quantum = number(j["quantum"], source, join(path, "quantum"));
    if (!(ch.quantum >= 0) || !std::isfinite(ch.quantum))
      fail(source, join(path, "quantum"), "must be finite and >= 0, got " + j["quantum"].dump());
  }
  parse_clock_keys(j, ch, source, path);
}

Json terms_json(const kernels::NoiseTerms& t) {
  Json j = Json::object();
  for (units::Term term : units::all_terms())
    j[std::string(units::term_name(term))] = term_value(t, term);
  return j;
}

// An effect's object: its type, then its keys in their order, each as its Presence says.
template <class E>
Json effect_json(const E& x) {
  Json j = Json::object();
  j["type"] = std::string(kernels::EffectTraits<E>::name);
  for (const auto& k : kernels::EffectTraits<E>::keys)
    if (kernels::written(k, x)) j[std::string(k.name)] = x.*k.field;
  return j;
}

Json channel_body_json(const Channel& ch) {
  Json j = Json::object();
  j["units"] = ch.units;
  j["terms"] = terms_json(ch.terms);
  Json effects = Json::array();
  kernels::for_each_effect_list(ch, [&](const auto& list) {
    for (const auto& x : list)
      effects.push_back(effect_json(x));
  });
  if (ch.lowpass.active()) effects.push_back(effect_json(ch.lowpass));
  j["effects"] = effects;
  if (ch.offset != 0) j["offset"] = ch.offset;
  if (ch.quantum != 0) j["quantum"] = ch.quantum;
  if (ch.powerlaw != std::array<double, 5>{}) {
    Json levels = Json::object();
    for (std::size_t i = 0; i < ch.powerlaw.size(); ++i)
      if (ch.powerlaw[i] != 0) levels[kernels::powerlaw::kLevelKeys[i]] = ch.powerlaw[i];
    j["powerlaw"] = levels;
  }
  if (ch.phase_output) j["output"] = "phase";
  return j;
}

}  // namespace

UnitModel parse_model(std::string_view json_text, const std::string& source,
                      const std::string& single_channel_name) {
  // Duplicate keys: JSON leaves them undefined and nlohmann keeps the last silently; a model
  // whose meaning depends on that is rejected. The callback tracks the keys of each open
  // object.
  std::vector<std::set<std::string>> open;
  std::string duplicate;
  const Json::parser_callback_t cb = [&](int, Json::parse_event_t ev, Json& parsed) {
    if (ev == Json::parse_event_t::object_start) open.emplace_back();
    if (ev == Json::parse_event_t::object_end && !open.empty()) open.pop_back();
    if (ev == Json::parse_event_t::key && !open.empty() && duplicate.empty()) {
      const auto key = parsed.get<std::string>();
      if (!open.back().insert(key).second) duplicate = key;
    }
    return true;
  };
  Json root;
  try {
    root = Json::parse(json_text.begin(), json_text.end(), cb);
  } catch (const Json::exception& e) {
    fail(source, "", std::string("invalid JSON: ") + e.what());
  }
  if (!duplicate.empty()) fail(source, duplicate, "duplicate key");
  object(root, source, "");

  UnitModel m;
  m.sample_rate_hz =
      positive(required(root, "sample_rate_hz", source, ""), source, "sample_rate_hz");
  if (root.contains("channels")) {
    only_keys(root, {"sample_rate_hz", "channels", "lot_spread"}, source, "");
    const Json& chans = object(root["channels"], source, "channels");
    if (chans.empty()) fail(source, "channels", "must not be empty");
    for (const auto& [name, body] : chans.items()) {
      const std::string path = join("channels", name);
      if (!valid_name(name))
        fail(source, path, "bad channel name (only letters, digits and _ are allowed)");
      object(body, source, path);
      only_keys(body, {"units", "terms", "effects", "offset", "quantum", "powerlaw", "output"},
                source, path);
      Channel ch;
      ch.name = name;
      parse_channel_body(body, m.sample_rate_hz, ch, source, path);
      m.channels.push_back(std::move(ch));
    }
  } else {
    only_keys(root,
              {"units", "sample_rate_hz", "terms", "effects", "offset", "quantum", "lot_spread",
               "powerlaw", "output"},
              source, "");
    if (!valid_name(single_channel_name))
      fail(source, "", "bad channel name '" + single_channel_name + "'");
    Channel ch;
    ch.name = single_channel_name;
    parse_channel_body(root, m.sample_rate_hz, ch, source, "");
    m.channels.push_back(std::move(ch));
    m.single_channel = true;
  }
  if (root.contains("lot_spread"))
    m.lot_spread = parse_terms(root["lot_spread"], source, "lot_spread");
  return m;
}

UnitModel load_model(const std::string& path, const std::string& single_channel_name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the model file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(path + ": cannot read the model file");
  return parse_model(text.str(), path, single_channel_name);
}

std::string to_json(const UnitModel& m) {
  Json root = Json::object();
  if (m.single_channel && m.channels.size() == 1) {
    const Json body = channel_body_json(m.channels[0]);
    root["units"] = body["units"];
    root["sample_rate_hz"] = m.sample_rate_hz;
    for (const auto& [key, value] : body.items())
      if (key != "units") root[key] = value;
  } else {
    root["sample_rate_hz"] = m.sample_rate_hz;
    Json chans = Json::object();
    for (const auto& ch : m.channels)
      chans[ch.name] = channel_body_json(ch);
    root["channels"] = chans;
  }
  if (m.lot_spread != kernels::NoiseTerms{}) root["lot_spread"] = terms_json(m.lot_spread);
  return root.dump(2) + "\n";
}

void validate(const UnitModel& m, const std::string& source) {
  // The JSON form is the single definition of validity: a model built in code is valid
  // exactly when its JSON parses. Non-finite numbers have no JSON form (nlohmann writes null),
  // which parse_model rejects as "must be a number".
  std::set<std::string> names;
  for (const auto& ch : m.channels)
    if (!names.insert(ch.name).second) fail(source, join("channels", ch.name), "duplicate channel");
  parse_model(to_json(m), source, m.channels.empty() ? "gyro_x" : m.channels[0].name);
}

UnitModel default_demo_model() {
  struct Row {
    const char* name;
    const char* units;
    double R, K, B, N;  // the Table's values in its units; Q = 0 on every axis
    double offset;
  };
  // Table of the paper: gyros R deg/h/h, K deg/h/sqrt(h), B deg/h, N deg/h/sqrt(Hz);
  // accelerometers R mg/h, K mg/sqrt(h), B mg, N mg/sqrt(Hz).
  const Row rows[] = {
      {"gyro_x", "deg/s", 0.00, 0.10, 4.50, 18.00, 0},
      {"gyro_y", "deg/s", 0.00, 0.00, 3.00, 4.00, 0},
      {"gyro_z", "deg/s", 0.02, 0.00, 0.70, 5.80, 0},
      {"accel_x", "m/s^2", 0.0019, 0.0071, 0.0175, 0.0295, 0},
      {"accel_y", "m/s^2", 0.0026, 0.001, 0.0160, 0.0410, 0},
      {"accel_z", "m/s^2", 0.0009, 0.0050, 0.0160, 0.0240, 9.80665},
  };
  UnitModel m;
  m.sample_rate_hz = 1000;  // the paper's 1.0 ms sampling interval
  for (const Row& r : rows) {
    Channel ch;
    ch.name = r.name;
    ch.units = r.units;
    const bool gyro = units::family_of(r.units) == units::Family::Gyro;
    using units::Term;
    ch.terms.R = units::from_datasheet(Term::R, r.R, gyro ? "deg/h/h" : "mg/h", r.units);
    ch.terms.K =
        units::from_datasheet(Term::K, r.K, gyro ? "deg/h/sqrt(h)" : "mg/sqrt(h)", r.units);
    ch.terms.B = units::from_datasheet(Term::B, r.B, gyro ? "deg/h" : "mg", r.units);
    ch.terms.N =
        units::from_datasheet(Term::N, r.N, gyro ? "deg/h/sqrt(Hz)" : "mg/sqrt(Hz)", r.units);
    ch.offset = r.offset;
    m.channels.push_back(std::move(ch));
  }
  m.lot_spread = {0.3, 0.3, 0.2, 0.1, 0.0};
  return m;
}

std::uint64_t channel_stream(int unit_index, std::size_t channel) {
  if (unit_index < 0) throw std::invalid_argument("channel_stream: unit_index must be >= 0");
  if (channel >= (std::size_t{1} << 20))
    throw std::invalid_argument("channel_stream: channel must be < 2^20");
  return (static_cast<std::uint64_t>(unit_index) << 20) | channel;
}

UnitModel draw_unit(const UnitModel& lot, std::uint64_t seed, int unit_index) {
  if (unit_index < 0)
    throw std::invalid_argument("draw_unit: unit_index must be >= 0, got " +
                                std::to_string(unit_index));
  UnitModel unit = lot;
  unit.lot_spread = {};
  const auto comp = static_cast<std::uint32_t>(kernels::rng::Component::LotSpread);
  for (std::size_t c = 0; c < unit.channels.size(); ++c) {
    const std::uint64_t stream = channel_stream(unit_index, c);
    std::uint64_t index = 0;
    for (units::Term term : units::all_terms()) {
      const double spread = term_value(lot.lot_spread, term);
      const double g = kernels::rng::normal(seed, stream, comp, index++);
      if (spread <= 0) continue;
      const double s2 = std::log1p(spread * spread);
      *term_field(unit.channels[c].terms, term) *= std::exp(std::sqrt(s2) * g - s2 / 2);
    }
  }
  return unit;
}

kernels::ChannelSpec to_spec(const UnitModel& m, std::size_t channel) {
  if (channel >= m.channels.size())
    throw std::invalid_argument("to_spec: channel " + std::to_string(channel) + " of " +
                                std::to_string(m.channels.size()));
  const Channel& ch = m.channels[channel];
  kernels::ChannelSpec s = ch;  // the channel's noise model, at the unit's rate
  s.rate_hz = m.sample_rate_hz;
  // Power-law levels join eq. (3)'s terms they equal (variances add; kernels/powerlaw/theory.hpp)
  // and flicker PM, which eq. (3) lacks.
  const auto& h = ch.powerlaw;
  const kernels::powerlaw::Eq3Squares e =
      kernels::powerlaw::eq3_squares(h[0], h[2], h[3], h[4], 1.0 / m.sample_rate_hz);
  s.terms.Q = std::sqrt(s.terms.Q * s.terms.Q + e.q2);
  s.terms.N = std::sqrt(s.terms.N * s.terms.N + e.n2);
  s.terms.B = std::sqrt(s.terms.B * s.terms.B + e.b2);
  s.terms.K = std::sqrt(s.terms.K * s.terms.K + e.k2);
  s.flicker_pm = h[1];
  return s;
}

}  // namespace allanlot::model
