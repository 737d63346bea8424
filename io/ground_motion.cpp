// Recorded ground motions prepared for a run (io/ground_motion.h): the components windowed,
// scaled, baseline-corrected and integrated step by step as the run reaches each step; the
// files themselves are read in record_files.cpp.
#include "io/ground_motion.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ishibashi {

GroundMotionStream::GroundMotionStream(const GroundMotionSpec& spec, double dt_s) : dt_s_(dt_s), start_s_(spec.start_s) {
  double end = INFINITY;
  std::filesystem::path shortest;  // the component whose record ends first
  bool any = false;
  for (int c = 0; c < 3; ++c) {
    if (!spec.component[c]) continue;
    const ComponentSpec& cs = *spec.component[c];
    Record r;
    if (cs.format == "at2") r = read_at2(cs.file);
    else if (cs.format == "knet") r = read_knet(cs.file);
    else if (cs.format == "columns") r = read_columns(cs.file, cs.unit, cs.layout);
    else throw InputError(cs.file.string() + ": unknown format '" + cs.format + "' (at2, knet or columns)");
    for (double& a : r.accel_m_s2) a *= cs.scale;
    const double length_s = r.dt_s * (r.accel_m_s2.size() - 1);
    if (length_s < end) end = length_s, shortest = cs.file;
    record_[c] = std::move(r);
    any = true;
  }
  if (!any) throw InputError("ground motion: no component given (x, y or z)");
  if (spec.start_s < 0 || spec.start_s >= end) {
    std::ostringstream message;
    message << "ground motion: start_s = " << spec.start_s << " s (a scenario's [ground_motion] start_s, a sweep record's, or "
            << "--start) lies outside the record; it must lie in [0, " << end << ") s, the length of its shortest component, "
            << shortest.string();
    throw InputError(message.str());
  }
  const double duration = spec.duration_s > 0 ? std::min(spec.duration_s, end - spec.start_s) : end - spec.start_s;
  steps_ = static_cast<long>(std::floor(duration / dt_s));

  if (spec.baseline_correction) {
    // Remove the least-squares linear trend of the velocity (a constant offset of the
    // acceleration), so that the ground does not drift away at the end of the record.
    const long n = steps_ + 1;
    for (int c = 0; c < 3; ++c) {
      if (!record_[c]) continue;
      double v = 0, a = acceleration_at(0)[c];
      double st = 0, sv = 0, stt = 0, stv = 0;
      for (long k = 0; k < n; ++k) {
        if (k > 0) {
          const double next = acceleration_at(k)[c];
          v = v + 0.5 * (a + next) * dt_s;
          a = next;
        }
        const double t = k * dt_s;
        st += t;
        sv += v;
        stt += t * t;
        stv += t * v;
      }
      baseline_m_s2_[c] = (n * stv - st * sv) / (n * stt - st * st);
    }
  }
  rewind_to(0);
}

Vec3 GroundMotionStream::acceleration_at(long step) const {
  Vec3 a = Vec3::Zero();
  for (int c = 0; c < 3; ++c) {
    if (!record_[c]) continue;
    const std::vector<double>& r = record_[c]->accel_m_s2;
    const double t = (start_s_ + step * dt_s_) / record_[c]->dt_s;
    const std::size_t i = std::min(static_cast<std::size_t>(t), r.size() - 2);
    const double f = t - i;
    a[c] = (1 - f) * r[i] + f * r[i + 1];
    a[c] -= baseline_m_s2_[c];
  }
  return a;
}

void GroundMotionStream::advance() {
  const Vec3 accel = acceleration_at(step_ + 1);
  const Vec3 velocity = velocity_ + 0.5 * (accel_ + accel) * dt_s_;
  displacement_ = displacement_ + 0.5 * (velocity_ + velocity) * dt_s_;
  velocity_ = velocity;
  accel_ = accel;
  ++step_;
}

void GroundMotionStream::rewind_to(long step) {
  step_ = 0;
  accel_ = acceleration_at(0);
  velocity_ = displacement_ = Vec3::Zero();
  while (step_ < step) advance();
}

GroundMotion prepare_ground_motion(const GroundMotionSpec& spec, double dt_s) {
  GroundMotionStream stream(spec, dt_s);
  GroundMotion g;
  g.dt_s = dt_s;
  for (;; stream.advance()) {
    g.accel_m_s2.push_back(stream.accel_m_s2());
    g.velocity_m_s.push_back(stream.velocity_m_s());
    g.displacement_m.push_back(stream.displacement_m());
    if (stream.step() == stream.steps()) return g;
  }
}

GroundMotionPeaks ground_motion_peaks(const GroundMotionSpec& spec) {
  const GroundMotion g = prepare_ground_motion(spec, 0.005);  // interpolation never exceeds a sample
  GroundMotionPeaks p;
  for (std::size_t k = 0; k < g.accel_m_s2.size(); ++k) {
    p.accel_m_s2 = p.accel_m_s2.cwiseMax(g.accel_m_s2[k].cwiseAbs());
    p.velocity_m_s = p.velocity_m_s.cwiseMax(g.velocity_m_s[k].cwiseAbs());
    p.displacement_m = p.displacement_m.cwiseMax(g.displacement_m[k].cwiseAbs());
  }
  return p;
}

double horizontal_pga_m_s2(const GroundMotionSpec& spec) {
  const Vec3 a = ground_motion_peaks(spec).accel_m_s2;
  return std::max(a.x(), a.y());
}

double arias_time_s(const GroundMotion& g, double fraction) {
  double total = 0;
  for (const Vec3& a : g.accel_m_s2) total += a.x() * a.x() + a.y() * a.y();
  double sum = 0;
  for (std::size_t k = 0; k < g.accel_m_s2.size(); ++k) {
    const Vec3& a = g.accel_m_s2[k];
    sum += a.x() * a.x() + a.y() * a.y();
    if (sum >= fraction * total) return k * g.dt_s;
  }
  return g.duration_s();
}

}  // namespace ishibashi
