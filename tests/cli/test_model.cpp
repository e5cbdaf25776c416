// The model file: the example of docs/formats.md parses, every rule is enforced with the key
// path in the message, to_json round-trips, the demo unit carries the paper's Table, lot draws are
// deterministic and have the promised spread.
#include "kernels/model/units.hpp"
#include "src/lot/model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace allanlot {
namespace {

// The example model of docs/formats.md "Model file".
constexpr const char* kContractExample = R"({
  "units": "deg/s",
  "sample_rate_hz": 1000,
  "terms":   {"R": 0, "K": 4.6e-7, "B": 0.00125, "N": 0.005, "Q": 0},
  "effects": [
    {"type": "sinusoid", "amplitude": 0.002, "frequency_hz": 0.5},
    {"type": "markov",   "sigma": 0.001, "tau_c_s": 20},
    {"type": "resonance", "sigma": 0.2, "frequency_hz": 19.5, "q": 80}
  ]
})";

constexpr const char* kUnitExample = R"({
  "sample_rate_hz": 200,
  "channels": {
    "gyro_z": {"units": "deg/s", "terms": {"N": 0.005, "B": 0.001}},
    "accel_z": {"units": "m/s^2", "terms": {"N": 3e-4}, "offset": 9.80665,
                "effects": [{"type": "sinusoid", "amplitude": 0.01, "frequency_hz": 100,
                             "phase_rad": 1.5}]},
    "gyro_x": {"units": "deg/s"}
  },
  "lot_spread": {"N": 0.1, "B": 0.2}
})";

TEST(Model, ParsesTheContractExample) {
  const auto m = model::parse_model(kContractExample, "model.json");
  EXPECT_TRUE(m.single_channel);
  ASSERT_EQ(m.channels.size(), 1u);
  const auto& ch = m.channels[0];
  EXPECT_EQ(ch.name, "gyro_x");
  EXPECT_EQ(ch.units, "deg/s");
  EXPECT_EQ(m.sample_rate_hz, 1000);
  EXPECT_EQ(ch.terms.K, 4.6e-7);
  EXPECT_EQ(ch.terms.N, 0.005);
  ASSERT_EQ(ch.sinusoids.size(), 1u);
  EXPECT_EQ(ch.sinusoids[0].frequency_hz, 0.5);
  EXPECT_EQ(ch.sinusoids[0].phase_rad, 0.0);
  ASSERT_EQ(ch.markovs.size(), 1u);
  EXPECT_EQ(ch.markovs[0].tau_c_s, 20);
  ASSERT_EQ(ch.resonances.size(), 1u);
  EXPECT_EQ(ch.resonances[0], (kernels::Resonance{0.2, 19.5, 80}));
  EXPECT_EQ(model::parse_model(kContractExample, "m.json", "gyro_z").channels[0].name, "gyro_z");
}

TEST(Model, UnitModelKeepsChannelOrder) {
  const auto m = model::parse_model(kUnitExample, "unit.json");
  EXPECT_FALSE(m.single_channel);
  ASSERT_EQ(m.channels.size(), 3u);
  EXPECT_EQ(m.channels[0].name, "gyro_z");
  EXPECT_EQ(m.channels[1].name, "accel_z");
  EXPECT_EQ(m.channels[2].name, "gyro_x");
  EXPECT_EQ(m.channels[1].offset, 9.80665);
  EXPECT_EQ(m.channels[1].sinusoids[0].frequency_hz, 100);  // exactly Nyquist is allowed
  EXPECT_EQ(m.lot_spread.N, 0.1);
  EXPECT_EQ(m.lot_spread.B, 0.2);
  EXPECT_EQ(m.lot_spread.K, 0.0);
  const auto spec = model::to_spec(m, 1);
  EXPECT_EQ(spec.rate_hz, 200);
  EXPECT_EQ(spec.offset, 9.80665);
  EXPECT_EQ(spec.terms.N, 3e-4);
  EXPECT_THROW(model::to_spec(m, 3), std::invalid_argument);
}

TEST(Model, ToJsonRoundTrips) {
  for (const auto& m :
       {model::parse_model(kContractExample, "a.json"), model::parse_model(kUnitExample, "b.json"),
        model::default_demo_model(), model::draw_unit(model::default_demo_model(), 5, 3)}) {
    const std::string text = model::to_json(m);
    const auto back = model::parse_model(text, "roundtrip.json");
    EXPECT_EQ(back, m) << text;
    EXPECT_EQ(model::to_json(back), text);
  }
}

TEST(Model, LowpassRoundTripsAndReachesTheSpec) {
  for (const char* effect :
       {R"({"type": "lowpass", "cutoff_hz": 20})", R"({"type": "lowpass", "taps": 4})"}) {
    const std::string text = std::string(R"({"sample_rate_hz": 100, "units": "deg/s",
        "terms": {"N": 0.01}, "effects": [)") +
                             effect + "]}";
    const auto m = model::parse_model(text, "lp.json");
    const auto back = model::parse_model(model::to_json(m), "roundtrip.json");
    EXPECT_EQ(back, m);
    const kernels::ChannelSpec s = model::to_spec(m, 0);
    EXPECT_TRUE(s.lowpass.active());
    EXPECT_EQ(s.lowpass, m.channels[0].lowpass);
  }
}

TEST(Model, StepRoundTripsAndReachesTheSpec) {
  const auto m = model::parse_model(R"({"sample_rate_hz": 100, "units": "deg/s",
      "terms": {"N": 0.01}, "effects": [{"type": "step", "size": -0.25, "time_s": 12.5},
      {"type": "step", "size": 0.1, "time_s": 40}]})",
                                    "step.json");
  ASSERT_EQ(m.channels[0].steps.size(), 2u);
  EXPECT_EQ(m.channels[0].steps[0], (kernels::Step{-0.25, 12.5}));
  EXPECT_EQ(model::parse_model(model::to_json(m), "roundtrip.json"), m);
  EXPECT_EQ(model::to_spec(m, 0).steps, m.channels[0].steps);
}

// A wandering resonance: spread_hz with its wander_s, written back only when the spread is not 0.
TEST(Model, WanderingResonanceRoundTripsAndReachesTheSpec) {
  const auto m = model::parse_model(R"({"sample_rate_hz": 100, "units": "deg/s",
      "effects": [{"type": "resonance", "sigma": 0.3, "frequency_hz": 19.9, "q": 31,
                   "spread_hz": 0.59, "wander_s": 770},
                  {"type": "resonance", "sigma": 0.2, "frequency_hz": 21.3, "q": 5}]})",
                                    "wander.json");
  ASSERT_EQ(m.channels[0].resonances.size(), 2u);
  EXPECT_EQ(m.channels[0].resonances[0], (kernels::Resonance{0.3, 19.9, 31, 0.59, 770}));
  EXPECT_EQ(m.channels[0].resonances[1], (kernels::Resonance{0.2, 21.3, 5}));
  const std::string text = model::to_json(m);
  EXPECT_EQ(model::parse_model(text, "roundtrip.json"), m);
  EXPECT_EQ(text.find("spread_hz"), text.rfind("spread_hz"));
  EXPECT_EQ(model::to_spec(m, 0).resonances, m.channels[0].resonances);
}

struct BadCase {
  const char* json;
  const char* expected;  // substring of the message after "bad.json: "
};

TEST(Model, BadFilesNameTheKey) {
  const BadCase cases[] = {
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"X": 1}})", "terms.X: unknown key"},
      {R"({"sample_rate_hz": 1000, "channels": {"gyro_x": {"units": "deg/s", "terms": {"X": 1}}}})",
       "channels.gyro_x.terms.X: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "colour": "red"})", "colour: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "device_id": "a"})", "device_id: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"N": -1}})",
       "terms.N: must be >= 0"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"N": "0.1"}})",
       "terms.N: must be a number"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"N": true}})",
       "terms.N: must be a number"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"N": null}})",
       "terms.N: must be a number"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": [1, 2]})",
       "terms: must be an object"},
      {R"({"sample_rate_hz": 0, "units": "deg/s"})", "sample_rate_hz: must be > 0"},
      {R"({"sample_rate_hz": -5, "units": "deg/s"})", "sample_rate_hz: must be > 0"},
      {R"({"sample_rate_hz": "1000", "units": "deg/s"})", "sample_rate_hz: must be a number"},
      {R"({"units": "deg/s"})", "sample_rate_hz: missing"},
      {R"({"sample_rate_hz": 1000})", "units: missing"},
      {R"({"sample_rate_hz": 1000, "units": ""})", "units: must be a non-empty string"},
      {R"({"sample_rate_hz": 1000, "units": 3})", "units: must be a non-empty string"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "sinusoid",
           "amplitude": 1, "frequency_hz": 600}]})",
       "effects[0].frequency_hz: must not exceed the Nyquist frequency"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "sinusoid",
           "amplitude": 1, "frequency_hz": 0}]})",
       "effects[0].frequency_hz: must be > 0"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "sinusoid",
           "frequency_hz": 1}]})",
       "effects[0].amplitude: missing"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "lowpass",
           "cutoff_hz": 50}]})",
       "effects[0].cutoff_hz: must be below the Nyquist frequency"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "lowpass",
           "cutoff_hz": 5, "taps": 3}]})",
       "effects[0]: a lowpass has exactly one of cutoff_hz and taps"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "lowpass",
           "taps": 1}]})",
       "effects[0].taps: must be in (1, 100000]"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "lowpass",
           "taps": 2}, {"type": "lowpass", "taps": 3}]})",
       "effects[1]: at most one lowpass effect"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 50, "q": 10}]})",
       "effects[0].frequency_hz: must be below the Nyquist frequency 50"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 20, "q": 0.3}]})",
       "effects[0].q: must be in [0.5, 100000"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 20}]})",
       "effects[0].q: missing"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 20, "q": 3, "tau_c_s": 1}]})",
       "effects[0].tau_c_s: unknown key"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 20, "q": 3, "spread_hz": 0.5}]})",
       "effects[0].wander_s: missing"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 20, "q": 3, "spread_hz": 4.5, "wander_s": 60}]})",
       "effects[0].spread_hz: must be at most 4"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "resonance",
           "sigma": 1, "frequency_hz": 20, "q": 3, "spread_hz": 0.5, "wander_s": 0}]})",
       "effects[0].wander_s: must be > 0"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "markov",
           "sigma": 1, "tau_c_s": 0}]})",
       "effects[0].tau_c_s: must be > 0"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "step",
           "size": 1, "time_s": 0}]})",
       "effects[0].time_s: must be > 0"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "step",
           "time_s": 3}]})",
       "effects[0].size: missing"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "step",
           "size": "big", "time_s": 3}]})",
       "effects[0].size: must be a number"},
      {R"({"sample_rate_hz": 100, "units": "deg/s", "effects": [{"type": "step",
           "size": 1, "time_s": 3, "width": 2}]})",
       "effects[0].width: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "markov",
           "sigma": 1, "tau_c_s": -3}]})",
       "effects[0].tau_c_s: must be > 0"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "markov",
           "sigma": -1, "tau_c_s": 3}]})",
       "effects[0].sigma: must be >= 0"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"type": "markov",
           "sigma": 1, "tau_c_s": 3, "beta": 2}]})",
       "effects[0].beta: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [
           {"type": "markov", "sigma": 1, "tau_c_s": 3}, {"type": "spike"}]})",
       "effects[1].type: unknown effect type 'spike'"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": [{"amplitude": 1}]})",
       "effects[0].type: missing"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "effects": {"type": "markov"}})",
       "effects: must be an array"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "offset": "g"})", "offset: must be a number"},
      {R"({"sample_rate_hz": 1000, "channels": {}})", "channels: must not be empty"},
      {R"({"sample_rate_hz": 1000, "channels": []})", "channels: must be an object"},
      {R"({"sample_rate_hz": 1000, "channels": {"gyro x": {"units": "deg/s"}}})",
       "channels.gyro x: bad channel name"},
      {R"({"sample_rate_hz": 1000, "channels": {"../etc": {"units": "deg/s"}}})",
       "channels.../etc: bad channel name"},
      {R"({"sample_rate_hz": 1000, "channels": {"": {"units": "deg/s"}}})", "bad channel name"},
      {R"({"sample_rate_hz": 1000, "channels": {"gyro_x": 5}})",
       "channels.gyro_x: must be an object"},
      {R"({"sample_rate_hz": 1000, "channels": {"gyro_x": {"terms": {}}}})",
       "channels.gyro_x.units: missing"},
      {R"({"sample_rate_hz": 1000, "channels": {"gyro_x": {"units": "deg/s", "lot_spread": {}}}})",
       "channels.gyro_x.lot_spread: unknown key"},
      {R"({"sample_rate_hz": 1000, "channels": {"a": {"units": "deg/s"}}, "units": "deg/s"})",
       "units: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "lot_spread": {"N": -0.1}})",
       "lot_spread.N: must be >= 0"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "lot_spread": {"Z": 0.1}})",
       "lot_spread.Z: unknown key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"N": 1e999}})", "number overflow"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"N": 1, "N": 2}})",
       "N: duplicate key"},
      {R"({"sample_rate_hz": 1000, "units": "deg/s",)", "invalid JSON"},
      {R"([1, 2, 3])", "must be an object"},
      {R"(NaN)", "invalid JSON"},
  };
  for (const auto& c : cases) {
    try {
      model::parse_model(c.json, "bad.json");
      ADD_FAILURE() << "accepted: " << c.json;
    } catch (const model::Error& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("bad.json: ", 0), 0u) << msg;
      EXPECT_NE(msg.find(c.expected), std::string::npos)
          << "expected '" << c.expected << "' in: " << msg;
    }
  }
}

TEST(Model, LoadModelNamesTheFile) {
  const std::filesystem::path dir = ALLANLOT_TEST_TMP;
  std::filesystem::create_directories(dir);
  const auto good = dir / "model_good.json";
  std::ofstream(good) << kUnitExample;
  EXPECT_EQ(model::load_model(good.string()).channels.size(), 3u);
  const auto bad = dir / "model_bad.json";
  std::ofstream(bad) << R"({"sample_rate_hz": 1000, "units": "deg/s", "terms": {"X": 1}})";
  try {
    model::load_model(bad.string());
    FAIL();
  } catch (const model::Error& e) {
    EXPECT_EQ(std::string(e.what()), bad.string() + ": terms.X: unknown key");
  }
  EXPECT_THROW(model::load_model((dir / "missing.json").string()), model::Error);
}

TEST(Model, DemoUnitIsThePapersTable) {
  const auto m = model::default_demo_model();
  ASSERT_EQ(m.channels.size(), 6u);
  EXPECT_EQ(m.sample_rate_hz, 1000);
  const char* names[] = {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"};
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_EQ(m.channels[i].name, names[i]);
  using kernels::units::Term;
  namespace units = kernels::units;
  // Back to datasheet units: the Table's numbers.
  const auto ds = [&](std::size_t c, Term t) {
    return units::to_datasheet(
        t,
        [&] {
          const auto& x = m.channels[c].terms;
          return t == Term::R   ? x.R
                 : t == Term::K ? x.K
                 : t == Term::B ? x.B
                 : t == Term::N ? x.N
                                : x.Q;
        }(),
        m.channels[c].units);
  };
  EXPECT_NEAR(ds(0, Term::N).primary.value, 18.0, 1e-12);
  EXPECT_NEAR(ds(0, Term::B).primary.value, 4.5, 1e-12);
  EXPECT_NEAR(ds(0, Term::K).primary.value, 0.10, 1e-14);
  EXPECT_NEAR(ds(2, Term::R).primary.value, 0.02, 1e-14);
  EXPECT_NEAR(ds(5, Term::N).primary.value, 0.0240, 1e-15);
  EXPECT_NEAR(ds(3, Term::B).primary.value, 0.0175, 1e-15);
  EXPECT_NEAR(ds(4, Term::K).primary.value, 0.001, 1e-15);
  EXPECT_EQ(m.channels[0].terms.N, units::from_datasheet(Term::N, 18, "deg/h/sqrt(Hz)", "deg/s"));
  EXPECT_EQ(m.channels[5].offset, 9.80665);
  EXPECT_EQ(m.channels[3].offset, 0.0);
  EXPECT_NO_THROW(model::validate(m, "demo"));
}

TEST(Model, DrawUnitIsDeterministicAndHasTheSpread) {
  const auto lot = model::default_demo_model();
  const auto a = model::draw_unit(lot, 42, 7);
  EXPECT_EQ(a, model::draw_unit(lot, 42, 7));
  EXPECT_NE(a, model::draw_unit(lot, 42, 8));
  EXPECT_NE(a, model::draw_unit(lot, 43, 7));
  EXPECT_EQ(a.lot_spread, kernels::NoiseTerms{});
  EXPECT_EQ(a.channels[1].terms.K, 0.0);  // a zero term stays zero
  EXPECT_EQ(a.channels[0].terms.Q, 0.0);
  EXPECT_EQ(a.channels[5].offset, 9.80665);  // offsets and effects are not spread
  EXPECT_THROW(model::draw_unit(lot, 1, -1), std::invalid_argument);
  // Over 4000 units the factor of N (spread 0.1) has mean 1 and relative sd 0.1: the sample
  // mean has sd 0.1/sqrt(4000) = 0.0016, the sample sd has sd ~0.1/sqrt(2*4000) = 0.0011
  // (log-normal, slightly more); 5 sigma each.
  const double n0 = lot.channels[0].terms.N;
  double s1 = 0, s2 = 0;
  const int units = 4000;
  for (int u = 0; u < units; ++u) {
    const double f = model::draw_unit(lot, 99, u).channels[0].terms.N / n0;
    EXPECT_GT(f, 0.0);
    s1 += f;
    s2 += f * f;
  }
  const double mean = s1 / units, sd = std::sqrt(s2 / units - mean * mean);
  EXPECT_NEAR(mean, 1.0, 5 * 0.0016);
  EXPECT_NEAR(sd, 0.1, 5 * 0.0012);
}

TEST(Model, ChannelStreamsAreDistinct) {
  EXPECT_NE(model::channel_stream(0, 1), model::channel_stream(1, 0));
  EXPECT_EQ(model::channel_stream(2, 5), (std::uint64_t{2} << 20) | 5);
  EXPECT_THROW(model::channel_stream(-1, 0), std::invalid_argument);
}

TEST(Model, ValidateRejectsBadModelsBuiltInCode) {
  auto m = model::default_demo_model();
  m.channels[1].name = "gyro_x";
  EXPECT_THROW(model::validate(m, "code"), model::Error);
  m = model::default_demo_model();
  m.channels[0].terms.N = -1;
  EXPECT_THROW(model::validate(m, "code"), model::Error);
  m = model::default_demo_model();
  m.channels[0].terms.B = NAN;
  EXPECT_THROW(model::validate(m, "code"), model::Error);
}

}  // namespace
}  // namespace allanlot
