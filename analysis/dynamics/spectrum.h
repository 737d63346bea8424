// Fourier analysis of response histories (Eigen's FFT): amplitude spectra and the first
// clear spectral peak and every peak, for natural frequencies from impulse responses.
#pragma once
#include <vector>

namespace ishibashi {

struct Spectrum {
  std::vector<double> frequency_hz;
  std::vector<double> amplitude;
  double resolution_hz() const { return frequency_hz.size() > 1 ? frequency_hz[1] - frequency_hz[0] : 0.0; }
};

// One-sided amplitude spectrum of a signal sampled every dt_s, mean removed, Hann
// window, zero-padded to a power of two at least `pad` times the length. Scaled by the
// window's gain, so that a sine of amplitude A reads A at its peak (up to 15 % less where
// it falls between two bins of the unpadded length).
Spectrum amplitude_spectrum(const std::vector<double>& signal, double dt_s, int pad = 4);

struct SpectralPeak {
  double frequency_hz;
  double relative_amplitude;  // of the spectrum's largest amplitude (1: the largest peak)
};

// Every local maximum above `threshold` times the spectrum's largest amplitude (ignoring
// frequencies below `min_hz`), ascending in frequency, each refined by a parabola through
// the three bins around it.
std::vector<SpectralPeak> spectral_peaks(const Spectrum& s, double threshold = 0.05, double min_hz = 0.0);

// The lowest local maximum above `threshold` times the spectrum's largest amplitude
// (ignoring frequencies below `min_hz`), refined by a parabola through the three bins
// around it. Returns 0 when there is none.
double first_peak_hz(const Spectrum& s, double threshold = 0.3, double min_hz = 0.0);

}  // namespace ishibashi
