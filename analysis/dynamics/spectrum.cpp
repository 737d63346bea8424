#include "analysis/dynamics/spectrum.h"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>

namespace ishibashi {

Spectrum amplitude_spectrum(const std::vector<double>& signal, double dt_s, int pad) {
  const std::size_t n = signal.size();
  std::size_t size = 1;
  while (size < static_cast<std::size_t>(pad) * n) size <<= 1;
  double mean = 0;
  for (double v : signal) mean += v / static_cast<double>(n);
  std::vector<double> x(size, 0.0);
  double window_sum = 0;  // the window's gain on a sine is window_sum / 2 of its amplitude
  for (std::size_t i = 0; i < n; ++i) {
    const double window = 0.5 * (1 - std::cos(2 * M_PI * i / std::max<std::size_t>(1, n - 1)));
    x[i] = (signal[i] - mean) * window;
    window_sum += window;
  }
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> out;
  fft.fwd(out, x);
  Spectrum s;
  for (std::size_t k = 0; k <= size / 2; ++k) {
    s.frequency_hz.push_back(k / (size * dt_s));
    s.amplitude.push_back(window_sum > 0 ? std::abs(out[k]) * 2.0 / window_sum : 0.0);  // a sine's amplitude at its peak
  }
  return s;
}

std::vector<SpectralPeak> spectral_peaks(const Spectrum& s, double threshold, double min_hz) {
  double largest = 0;
  for (std::size_t k = 0; k < s.amplitude.size(); ++k)
    if (s.frequency_hz[k] >= min_hz) largest = std::max(largest, s.amplitude[k]);
  std::vector<SpectralPeak> peaks;
  for (std::size_t k = 1; k + 1 < s.amplitude.size(); ++k) {
    const double a = s.amplitude[k];
    if (s.frequency_hz[k] < min_hz || a <= 0 || a < threshold * largest) continue;
    if (a < s.amplitude[k - 1] || a < s.amplitude[k + 1]) continue;
    // Parabola through the three bins (on log amplitude: exact for a Gaussian-like peak).
    const double l = std::log(s.amplitude[k - 1]), c = std::log(a), r = std::log(s.amplitude[k + 1]);
    const double curvature = l - 2 * c + r;
    const double shift = curvature < 0 ? 0.5 * (l - r) / curvature : 0.0;
    peaks.push_back({s.frequency_hz[k] + shift * s.resolution_hz(), a / largest});
  }
  return peaks;
}

double first_peak_hz(const Spectrum& s, double threshold, double min_hz) {
  const std::vector<SpectralPeak> peaks = spectral_peaks(s, threshold, min_hz);
  return peaks.empty() ? 0.0 : peaks.front().frequency_hz;
}

}  // namespace ishibashi
