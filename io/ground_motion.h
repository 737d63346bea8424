// Recorded ground motions: readers for PEER NGA .AT2, K-NET/KiK-net ASCII and plain
// columns (time and acceleration, or acceleration at a given dt), and their preparation
// for a run: three components on x, y, z, scaled, windowed, resampled to the engine's dt,
// baseline-corrected, integrated to the ground's velocity and displacement.
//
// The ground motion drives the fixed units kinematically: every fixed block (ground,
// springers, side walls) moves with the ground's velocity; the other blocks feel it only
// through their contacts. (Not as an inertial load in the ground frame.)
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/math.h"
#include "io/model_file.h"

namespace ishibashi {

constexpr double kStandardGravity_m_s2 = 9.80665;  // records' g
enum class AccelerationUnit { g, gal, m_s2 };

struct Record {
  std::string source;            // file name, for messages
  double dt_s = 0.0;
  std::vector<double> accel_m_s2;
  double peak_m_s2() const;
};

// PEER NGA AT2: 4 header lines, the 4th "NPTS = n, DT = dt SEC", then n values (g).
Record read_at2(const std::filesystem::path& file);
// K-NET / KiK-net ASCII: header with "Sampling Freq(Hz)" and "Scale Factor
// a(gal)/b", "Memo." then counts; acceleration = counts * a / b, less its mean.
Record read_knet(const std::filesystem::path& file);
// Plain text or CSV: two columns (time s, acceleration) with uniform steps, or one
// column of accelerations at `dt_s` (> 0). Lines starting with '#' are comments, and the
// first `header_lines` lines are skipped. A file of several components (a row a sample:
// time, then the components, or the components alone at `dt_s`) is read one component at
// a time (ColumnLayout::column); every row has as many values as the first.
struct ColumnLayout {
  double dt_s = 0.0;     // > 0: no time column, samples at this step
  int column = 0;        // the acceleration's column, from 1; 0: the last of two, or the only one
  int header_lines = 0;  // lines skipped before the samples (a header: names, units, station)
};
Record read_columns(const std::filesystem::path& file, AccelerationUnit unit, const ColumnLayout& layout = {});

struct ComponentSpec {
  std::filesystem::path file;
  std::string format = "at2";            // "at2", "knet" or "columns"
  AccelerationUnit unit = AccelerationUnit::g;  // for "columns"
  ColumnLayout layout;                   // for "columns"
  double scale = 1.0;
};

struct GroundMotionSpec {
  std::array<std::optional<ComponentSpec>, 3> component;  // x, y, z
  double start_s = 0.0;       // skip this much of the record
  double duration_s = 0.0;    // 0: to the end of the shortest component
  bool baseline_correction = true;
};

// The ground's motion at the engine's steps (step k at time k * dt_s from the window's
// start), computed as a run reaches each step: it keeps the records, not a table per
// step, so a run's memory does not grow with its duration (a table of 10 s at 4e-6 s is
// 180 MB, of a whole record GBs, per ensemble member). The acceleration is the records
// interpolated linearly, scaled, less the baseline's constant; velocity and displacement
// are their trapezoidal sums from rest, the same additions in the same order at any step.
class GroundMotionStream {
 public:
  GroundMotionStream() = default;
  GroundMotionStream(const GroundMotionSpec& spec, double dt_s);

  double dt_s() const { return dt_s_; }
  long steps() const { return steps_; }  // the last step: the motion lasts steps() * dt_s()
  double duration_s() const { return dt_s_ * steps_; }

  long step() const { return step_; }  // where the stream is; the values below are there
  const Vec3& accel_m_s2() const { return accel_; }
  const Vec3& velocity_m_s() const { return velocity_; }
  const Vec3& displacement_m() const { return displacement_; }

  void advance();             // to step() + 1 (at most steps())
  void rewind_to(long step);  // from step 0 again (a resumed run): about 16 ms a million steps

 private:
  Vec3 acceleration_at(long step) const;

  double dt_s_ = 0.0, start_s_ = 0.0;
  long steps_ = 0, step_ = 0;
  std::array<std::optional<Record>, 3> record_;  // x, y, z, scaled
  Vec3 baseline_m_s2_ = Vec3::Zero();            // the constant removed from each component
  Vec3 accel_ = Vec3::Zero(), velocity_ = Vec3::Zero(), displacement_ = Vec3::Zero();
};

// The same motion as a table (sample k at time k * dt_s), for analyses at a coarse step:
// spectra, Arias intensity, the report's plots.
struct GroundMotion {
  double dt_s = 0.0;
  std::vector<Vec3> accel_m_s2, velocity_m_s, displacement_m;
  double duration_s() const { return dt_s * (accel_m_s2.empty() ? 0 : accel_m_s2.size() - 1); }
};

GroundMotion prepare_ground_motion(const GroundMotionSpec& spec, double dt_s);

// The peaks of each component (x, y, z) of the motion as prepared (window, scale,
// baseline correction): |acceleration| m/s^2, |velocity| m/s, |displacement| m.
struct GroundMotionPeaks {
  Vec3 accel_m_s2 = Vec3::Zero(), velocity_m_s = Vec3::Zero(), displacement_m = Vec3::Zero();
};
GroundMotionPeaks ground_motion_peaks(const GroundMotionSpec& spec);

// The peak ground acceleration of the horizontal components (the larger of x and y), m/s^2.
double horizontal_pga_m_s2(const GroundMotionSpec& spec);

// The time (s from the motion's start) by which the horizontal components' Arias
// intensity, the integral of a_x^2 + a_y^2, reaches `fraction` of its total: 0.05 is where
// the strong motion begins (the significant duration D5-95, Trifunac and Brady 1975).
double arias_time_s(const GroundMotion& motion, double fraction);

}  // namespace ishibashi
