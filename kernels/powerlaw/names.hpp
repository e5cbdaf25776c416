// The names of the five power-law noise types of clocks (NIST SP1065 sec. 5.1, p. 20: the
// fractional frequency's one-sided PSD S_y(f) = h_alpha f^alpha): the one owner of the words
// "white PM", "flicker PM", "white FM", "flicker FM" and "random-walk FM" wherever an alpha is
// shown (terminal, results, report, lot summary).
#pragma once

#include <array>
#include <string_view>

namespace allanlot::kernels::powerlaw {

/// True for clock data, the channels the power-law model describes: units of a clock
/// (kernels::units::Family::Clock: s, time error, or 1, fractional frequency, which a frequency
/// in Hz read with a nominal frequency becomes), or phase data ("phase", "phase (default)") in
/// units outside the IMU families. Gyro and accelerometer channels are IMU data whatever their
/// data type (an angle recording is the phase of a gyro). The one owner of the rule: the
/// analysis, the terminal tables, the report and the lot page ask it.
bool is_clock_channel(std::string_view units, std::string_view data_type);

/// The exponents of the power-law model, in the order of every table: white PM (2), flicker PM
/// (1), white FM (0), flicker FM (-1), random-walk FM (-2).
inline constexpr std::array<int, 5> kAlphas = {2, 1, 0, -1, -2};
inline constexpr std::size_t kNumLevels = kAlphas.size();

/// The levels' short names, in the order of kAlphas: the model file's keys (docs/formats.md
/// "Model file") and the lot summary's columns (h2, h2_sigma, ...).
inline constexpr std::array<const char*, kNumLevels> kLevelKeys = {"h2", "h1", "h0", "hm1", "hm2"};

/// The index of alpha in kAlphas; throws std::invalid_argument outside -2..2.
std::size_t level_index(int alpha);

/// "white PM", "flicker PM", "white FM", "flicker FM", "random-walk FM" for alpha = 2 .. -2;
/// "" for any other alpha (the noise identification's alpha of a Hadamard statistic may be -3
/// or -4, flicker and random-run FM: see noise_type_name_long).
std::string_view noise_type_name(int alpha);

/// noise_type_name, extended to the exponents the Hadamard family identifies (SP1065 sec. 5.2.9):
/// "flicker walk FM" (-3), "random run FM" (-4); "" for any other alpha.
std::string_view noise_type_name_long(int alpha);

}  // namespace allanlot::kernels::powerlaw
