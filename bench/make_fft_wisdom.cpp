// Writes the FFTW wisdom stored with allanlot (kernels/spectral/fft_wisdom.txt) to standard
// output: FFTW_MEASURE plans of the real-to-complex transforms of every power of two the Welch
// PSD can use (kernels/spectral/psd.hpp welch_segment_length), from 2^4 to 2^24 samples, i.e.
// records of up to about 2^27 samples (37 hours at 1 kHz) with the default 16 segments. Run it
// on an idle machine of the project's kind and commit the file with the reason
// (docs/fit-and-psd.md "Reproducibility"):
//
//   build/bench/make_fft_wisdom > kernels/spectral/fft_wisdom.txt
#include "kernels/spectral/fft.hpp"

#include <cstdio>
#include <exception>
#include <vector>

int main() {
  try {
    std::vector<int> lengths;
    for (int n = 16; n <= (1 << 24); n *= 2)
      lengths.push_back(n);
    std::fputs(allanlot::kernels::fft::measure_r2c_wisdom(lengths).c_str(), stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_fft_wisdom: %s\n", e.what());
    return 1;
  }
}
