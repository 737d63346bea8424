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
// column of accelerations at `dt_s` (> 0). Lines starting with '#' are comments.
Record read_columns(const std::filesystem::path& file, AccelerationUnit unit, double dt_s = 0.0);

struct ComponentSpec {
  std::filesystem::path file;
  std::string format = "at2";            // "at2", "knet" or "columns"
  AccelerationUnit unit = AccelerationUnit::g;  // for "columns"
  double dt_s = 0.0;                     // for one-column files
  double scale = 1.0;
};

struct GroundMotionSpec {
  std::array<std::optional<ComponentSpec>, 3> component;  // x, y, z
  double start_s = 0.0;       // skip this much of the record
  double duration_s = 0.0;    // 0: to the end of the shortest component
  bool baseline_correction = true;
};

// The ground's motion at the engine's time step: sample k is at time k * dt_s.
struct GroundMotion {
  double dt_s = 0.0;
  std::vector<Vec3> accel_m_s2, velocity_m_s, displacement_m;
  double duration_s() const { return dt_s * (accel_m_s2.empty() ? 0 : accel_m_s2.size() - 1); }
};

GroundMotion prepare_ground_motion(const GroundMotionSpec& spec, double dt_s);

// The peak ground acceleration of the horizontal components (the larger of x and y) of
// the motion as prepared (window, scale, baseline correction), m/s^2.
double horizontal_pga_m_s2(const GroundMotionSpec& spec);

// The time (s from the motion's start) by which the horizontal components' Arias
// intensity, the integral of a_x^2 + a_y^2, reaches `fraction` of its total: 0.05 is where
// the strong motion begins (the significant duration D5-95, Trifunac and Brady 1975).
double arias_time_s(const GroundMotion& motion, double fraction);

}  // namespace ishibashi
