// Ground-motion readers and preparation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <malloc.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "io/ground_motion.h"

namespace ishibashi {
namespace {

using ::testing::HasSubstr;

const std::filesystem::path kKobe = std::filesystem::path(ISHIBASHI_SOURCE_DIR) / "data/ground_motions/kobe_1995_jma";

TEST(GroundMotion, KobeRecordsHaveTheirPublishedSizeAndPeaks) {
  const struct {
    const char* file;
    double peak_gal;
  } expected[] = {{"RSN1106_KOBE_KJM000.AT2", 818}, {"RSN1106_KOBE_KJM090.AT2", 617}, {"RSN1106_KOBE_KJM-UP.AT2", 332}};
  for (const auto& e : expected) {
    const Record r = read_at2(kKobe / e.file);
    EXPECT_EQ(r.accel_m_s2.size(), 7500u) << e.file;
    EXPECT_DOUBLE_EQ(r.dt_s, 0.02);
    EXPECT_NEAR(r.peak_m_s2() * 100.0, e.peak_gal, 1.0) << e.file;  // gal = cm/s^2
  }
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto f = std::filesystem::temp_directory_path() / name;
  std::ofstream(f) << text;
  return f;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(GroundMotion, MalformedFilesAreClearErrors) {
  const std::string header = "PEER\nevent\nACCELERATION TIME SERIES IN UNITS OF G\n";
  const auto mismatch = write("gm_count.AT2", header + "NPTS = 4, DT = .01 SEC\n 0.1 0.2 0.3\n");
  EXPECT_THAT(error_of([&] { read_at2(mismatch); }), HasSubstr("NPTS = 4 but the file holds 3 values"));
  const auto text = write("gm_text.AT2", header + "NPTS = 3, DT = .01 SEC\n 0.1 abc 0.3\n");
  EXPECT_THAT(error_of([&] { read_at2(text); }), HasSubstr("gm_text.AT2:5: 'abc' is not a number"));
  const auto headless = write("gm_header.AT2", "0.1 0.2\n0.3\n");
  EXPECT_THAT(error_of([&] { read_at2(headless); }), HasSubstr("AT2 header is incomplete"));
  const auto knet = write("gm.knet", "Origin Time 1995/01/17\n1 2 3\n");
  EXPECT_THAT(error_of([&] { read_knet(knet); }), HasSubstr("not a K-NET"));
  // Header numbers that are only points or out of range: the line and what belongs there,
  // not the bare "stod" of the standard library.
  const auto dot_dt = write("gm_dot.AT2", header + "NPTS = 3, DT = . SEC\n 0.1 0.2 0.3\n");
  EXPECT_THAT(error_of([&] { read_at2(dot_dt); }), HasSubstr("gm_dot.AT2:4: '.' is not a number: expected the time step DT"));
  const auto huge = write("gm_huge.AT2", header + "NPTS = 99999999999999999999999, DT = .01 SEC\n 0.1\n");
  EXPECT_THAT(error_of([&] { read_at2(huge); }), HasSubstr("gm_huge.AT2:4: NPTS = 99999999999999999999999 is beyond any record"));
  // The header line in any case and spacing, after other words, is read; a long damaged
  // one (a megabyte of "NPTS = 1, DT ") is an error, not a stack overflow.
  const auto spaced = write("gm_spaced.AT2", header + "x npts=2 ,dt=  0.02E0   sec, y\n 0.1 0.2\n");
  const Record spaced_record = read_at2(spaced);
  EXPECT_EQ(spaced_record.accel_m_s2.size(), 2u);
  EXPECT_DOUBLE_EQ(spaced_record.dt_s, 0.02);
  std::string damaged;
  for (int i = 0; i < 80000; ++i) damaged += "NPTS = 1, DT ";
  const auto long_line = write("gm_long.AT2", header + damaged + "\n 0.1\n");
  EXPECT_THAT(error_of([&] { read_at2(long_line); }), HasSubstr("gm_long.AT2:4: expected 'NPTS = n, DT = dt SEC'"));
  const std::string knet_tail = "Memo.\n1 2 3\n";
  const auto dot_hz = write("gm_hz.knet", "Sampling Freq(Hz)  .Hz\nScale Factor 7845(gal)/8223790\n" + knet_tail);
  EXPECT_THAT(error_of([&] { read_knet(dot_hz); }), HasSubstr("gm_hz.knet:1: '.' is not a number: expected the sampling frequency"));
  const auto no_hz = write("gm_nohz.knet", "Sampling Freq(Hz)  100\nScale Factor 7845(gal)/8223790\n" + knet_tail);
  EXPECT_THAT(error_of([&] { read_knet(no_hz); }), HasSubstr("gm_nohz.knet:1: cannot read the sampling frequency"));
  const auto zero_scale = write("gm_scale.knet", "Sampling Freq(Hz)  100Hz\nScale Factor 7845(gal)/0\n" + knet_tail);
  EXPECT_THAT(error_of([&] { read_knet(zero_scale); }), HasSubstr("gm_scale.knet:2: the scale factor's divisor must be positive"));
  const auto uneven = write("gm.csv", "0.0, 0.1\n0.01, 0.2\n0.03, 0.1\n");
  EXPECT_THAT(error_of([&] { read_columns(uneven, AccelerationUnit::gal); }), HasSubstr("not uniform"));
}

TEST(GroundMotion, KnetAndColumnsReadWithUnits) {
  const auto knet = write("gm_ok.knet",
                          "Origin Time       1995/01/17 05:46:00\nSampling Freq(Hz) 100Hz\n"
                          "Scale Factor      7845(gal)/8223790\nMemo.\n 1000 -1000 3000\n");
  const Record k = read_knet(knet);
  EXPECT_DOUBLE_EQ(k.dt_s, 0.01);
  // counts * 7845/8223790 gal, less the mean (1000 counts): +0, -2000, +2000 counts.
  EXPECT_NEAR(k.accel_m_s2[2], 2000 * 7845.0 / 8223790 * 0.01, 1e-12);
  const Record c = read_columns(write("gm_ok.csv", "# t, a\n0.0, 100\n0.5, -50\n"), AccelerationUnit::gal);
  EXPECT_DOUBLE_EQ(c.dt_s, 0.5);
  EXPECT_DOUBLE_EQ(c.accel_m_s2[1], -0.5);
  const Record one = read_columns(write("gm_one.txt", "0.1\n0.2\n0.3\n"), AccelerationUnit::g, {0.02});
  EXPECT_NEAR(one.accel_m_s2[2], 0.3 * 9.80665, 1e-12);
}

// A file of three components, as the JMA and many loggers write them: a header of names,
// then a row a sample. Each component reads its own column, with or without a time column.
TEST(GroundMotion, ColumnsOfSeveralComponentsReadOneAtATime) {
  const auto timed = write("gm_three.csv", "station KOBE, unit gal\ntime,NS,EW,UD\n0.00,100,-20,5\n0.01,-50,40,-7\n0.02,25,0,3\n");
  const Record ew = read_columns(timed, AccelerationUnit::gal, {.column = 3, .header_lines = 2});
  EXPECT_DOUBLE_EQ(ew.dt_s, 0.01);
  ASSERT_EQ(ew.accel_m_s2.size(), 3u);
  EXPECT_DOUBLE_EQ(ew.accel_m_s2[0], -0.2);  // gal -> m/s^2
  EXPECT_DOUBLE_EQ(ew.accel_m_s2[1], 0.4);
  EXPECT_DOUBLE_EQ(read_columns(timed, AccelerationUnit::gal, {.column = 4, .header_lines = 2}).accel_m_s2[1], -0.07);
  const auto untimed = write("gm_three.txt", "NS EW UD\n1 2 3\n4 5 6\n");
  const Record ud = read_columns(untimed, AccelerationUnit::m_s2, {.dt_s = 0.005, .column = 3, .header_lines = 1});
  EXPECT_DOUBLE_EQ(ud.dt_s, 0.005);
  EXPECT_DOUBLE_EQ(ud.accel_m_s2[1], 6.0);
  EXPECT_DOUBLE_EQ(read_columns(untimed, AccelerationUnit::m_s2, {.dt_s = 0.005, .column = 1, .header_lines = 1}).accel_m_s2[0], 1.0);

  // What is wrong, where, and what would be right.
  EXPECT_THAT(error_of([&] { read_columns(timed, AccelerationUnit::gal, {.column = 3}); }),
              HasSubstr("gm_three.csv:1: 'station' is not a number (a header? header_lines = 2 skips it: the samples start on line 3)"));
  EXPECT_THAT(error_of([&] { read_columns(timed, AccelerationUnit::gal, {.column = 5, .header_lines = 2}); }),
              HasSubstr("gm_three.csv:3: 4 values, so no column 5"));
  EXPECT_THAT(error_of([&] { read_columns(timed, AccelerationUnit::gal, {.column = 1, .header_lines = 2}); }),
              HasSubstr("column 1 holds the time"));
  EXPECT_THAT(error_of([&] { read_columns(timed, AccelerationUnit::gal, {.header_lines = 2}); }),
              HasSubstr("gm_three.csv:3: expected two columns: time (s) and acceleration; of a file of several columns, column = N"));
  const auto ragged = write("gm_ragged.csv", "0.00,1,2,3\n0.01,1,2\n");
  EXPECT_THAT(error_of([&] { read_columns(ragged, AccelerationUnit::gal, {.column = 2}); }),
              HasSubstr("gm_ragged.csv:2: 3 values where the first row has 4"));
  const auto bad_later = write("gm_bad.csv", "0.00,1\n0.01,x\n");  // no header hint past the first sample
  const std::string later = error_of([&] { read_columns(bad_later, AccelerationUnit::gal); });
  EXPECT_THAT(later, HasSubstr("gm_bad.csv:2: 'x' is not a number"));
  EXPECT_THAT(later, ::testing::Not(HasSubstr("header")));
}

// A one-column file of `values` (m/s^2) sampled every `dt_s`, as a motion's component.
ComponentSpec column_component(const std::string& name, const std::vector<double>& values, double dt_s) {
  std::ostringstream text;
  text.precision(17);
  for (double v : values) text << v << "\n";
  ComponentSpec cs;
  cs.file = write(name, text.str());
  cs.format = "columns";
  cs.unit = AccelerationUnit::m_s2;
  cs.layout.dt_s = dt_s;
  return cs;
}

// x: a 2 Hz sine of 1 m/s^2 plus `offset_m_s2`, 2 s (four periods) sampled at 0.01 s.
GroundMotionSpec sine_spec(double offset_m_s2, bool baseline_correction) {
  std::vector<double> values;
  for (int i = 0; i <= 200; ++i) values.push_back(offset_m_s2 + std::sin(2 * M_PI * 2.0 * i * 0.01));
  GroundMotionSpec spec;
  spec.component[0] = column_component("gm_sine.txt", values, 0.01);
  spec.baseline_correction = baseline_correction;
  return spec;
}

// The sine's closed-form velocity (1 - cos wt) / w and displacement t / w - sin(wt) / w^2.
void expect_sine_integrals(const GroundMotion& g) {
  const double w = 2 * M_PI * 2.0;
  for (std::size_t k : {250u, 1000u, 1730u}) {
    const double t = k * 1e-3;
    // Linear interpolation between samples 25 per period costs ~(w h)^2 / 8 = 0.2 %.
    EXPECT_NEAR(g.accel_m_s2[k].x(), std::sin(w * t), 0.01) << t;
    EXPECT_NEAR(g.velocity_m_s[k].x(), (1 - std::cos(w * t)) / w, 0.005 * (2 / w)) << t;
    EXPECT_NEAR(g.displacement_m[k].x(), t / w - std::sin(w * t) / (w * w), 0.005 * (t / w)) << t;
  }
}

TEST(GroundMotion, ResampledAndIntegratedConsistently) {
  // Resampled to 1e-3 s: the velocity and displacement follow the closed-form integrals.
  const GroundMotion g = prepare_ground_motion(sine_spec(0.0, false), 1e-3);
  EXPECT_EQ(g.accel_m_s2.size(), 2001u);
  expect_sine_integrals(g);
}

TEST(GroundMotion, BaselineCorrectionRemovesAConstantOffset) {
  // The sine plus 0.3 m/s^2 (a record's offset: 0.6 m/s of drift by 2 s, four times the
  // sine's velocity). Over whole periods the sine's velocity has no linear trend, so the
  // least-squares trend removed is the offset's, and the sine's integrals are left.
  expect_sine_integrals(prepare_ground_motion(sine_spec(0.3, true), 1e-3));
  // Without the correction the offset stays (what the check above must catch).
  const GroundMotion raw = prepare_ground_motion(sine_spec(0.3, false), 1e-3);
  EXPECT_NEAR(raw.velocity_m_s[2000].x(), 0.3 * 2.0, 0.01);
}

// Motions whose integrals the stream must reproduce to rounding: a constant acceleration
// and a ramp, both exactly linear between samples, resampled to a step that never meets
// the samples (0.1 s / 0.003 s is not whole).
TEST(GroundMotion, ConstantAndRampAccelerationsIntegrateExactly) {
  const double dt = 0.003;
  GroundMotionSpec constant;
  constant.component[0] = column_component("gm_constant.txt", std::vector<double>(11, 2.0), 0.1);
  constant.baseline_correction = false;
  const GroundMotion c = prepare_ground_motion(constant, dt);
  ASSERT_EQ(c.accel_m_s2.size(), 334u);  // floor(1 s / 0.003 s) steps, and the start
  for (std::size_t k = 0; k < c.accel_m_s2.size(); ++k) {
    const double t = k * dt;
    EXPECT_NEAR(c.velocity_m_s[k].x(), 2.0 * t, 1e-12) << t;
    EXPECT_NEAR(c.displacement_m[k].x(), t * t, 1e-12) << t;  // a t^2 / 2: the trapezoid's, not t (t + dt)
  }
  std::vector<double> ramp;  // a = t m/s^2, sampled every 0.1 s
  for (int i = 0; i <= 10; ++i) ramp.push_back(0.1 * i);
  GroundMotionSpec rising;
  rising.component[1] = column_component("gm_ramp.txt", ramp, 0.1);
  rising.baseline_correction = false;
  const GroundMotion r = prepare_ground_motion(rising, dt);
  for (std::size_t k = 0; k < r.accel_m_s2.size(); ++k) {
    const double t = k * dt;
    EXPECT_NEAR(r.accel_m_s2[k].y(), t, 1e-12) << t;  // between the samples, not the sample before
    EXPECT_NEAR(r.velocity_m_s[k].y(), t * t / 2, 1e-12) << t;
    EXPECT_EQ(r.accel_m_s2[k].x(), 0.0);
  }
}

// The header's peaks and the PGA a sweep scales to: magnitudes, whichever way the ground
// moves, and the PGA is the larger horizontal one, never the vertical.
TEST(GroundMotion, PeaksAreMagnitudesAndThePgaIsTheLargerHorizontalOne) {
  GroundMotionSpec spec;
  spec.component[0] = column_component("gm_peak_x.txt", std::vector<double>(11, 2.0), 0.1);
  spec.component[1] = column_component("gm_peak_y.txt", std::vector<double>(11, -3.0), 0.1);
  spec.component[2] = column_component("gm_peak_z.txt", std::vector<double>(11, 5.0), 0.1);
  spec.baseline_correction = false;
  const GroundMotionPeaks p = ground_motion_peaks(spec);
  // 1 s of constant acceleration a: |v| = |a| t and |d| = |a| t^2 / 2 at its end (to a step of 5 ms).
  EXPECT_NEAR(p.accel_m_s2.y(), 3.0, 1e-12);
  EXPECT_NEAR(p.velocity_m_s.y(), 3.0, 3.0 * 0.0051);
  EXPECT_NEAR(p.displacement_m.y(), 1.5, 3.0 * 0.0051);
  EXPECT_NEAR(p.velocity_m_s.x(), 2.0, 2.0 * 0.0051);
  EXPECT_NEAR(horizontal_pga_m_s2(spec), 3.0, 1e-12);
  std::swap(spec.component[0], spec.component[1]);
  EXPECT_NEAR(horizontal_pga_m_s2(spec), 3.0, 1e-12);
}

TEST(GroundMotion, AStartAtTheRecordsEndIsRefused) {
  GroundMotionSpec spec;
  spec.component[0] = column_component("gm_start.txt", std::vector<double>(11, 1.0), 0.1);  // 1 s long
  spec.start_s = 1.0;
  EXPECT_THAT(error_of([&] { GroundMotionStream(spec, 0.003); }), HasSubstr("start_s = 1 s"));
  EXPECT_THAT(error_of([&] { GroundMotionStream(spec, 0.003); }), HasSubstr("it must lie in [0, 1) s"));
  spec.start_s = 0.99;
  EXPECT_EQ(GroundMotionStream(spec, 0.003).steps(), 3);  // floor(0.01 s / 0.003 s)
}

// What the readers' headers say is what they read: AT2 in cm/s^2, any K-NET sampling rate,
// exactly NPTS values, and a time column's steps.
TEST(GroundMotion, HeadersUnitsRatesCountsAndTimesAreTheRecords) {
  const std::string peer = "PEER\nevent\nACCELERATION TIME SERIES IN UNITS OF ";
  const Record gal = read_at2(write("gm_gal.AT2", peer + "CM/S/S\nNPTS = 2, DT = .01 SEC\n 100 -50\n"));
  EXPECT_DOUBLE_EQ(gal.accel_m_s2[0], 1.0);
  EXPECT_DOUBLE_EQ(gal.accel_m_s2[1], -0.5);
  EXPECT_THAT(error_of([&] { read_at2(write("gm_ft.AT2", peer + "FT/S/S\nNPTS = 2, DT = .01 SEC\n 1 2\n")); }),
              HasSubstr("gm_ft.AT2:3: unknown acceleration units (expected 'UNITS OF G' or 'CM/S/S')"));
  EXPECT_THAT(error_of([&] { read_at2(write("gm_more.AT2", peer + "G\nNPTS = 2, DT = .01 SEC\n 1 2 3\n")); }),
              HasSubstr("NPTS = 2 but the file holds 3 values"));
  for (const double hz : {200.0, 50.0}) {
    const Record k = read_knet(write("gm_rate.knet", "Sampling Freq(Hz) " + std::to_string(int(hz)) +
                                                         "Hz\nScale Factor 7845(gal)/8223790\nMemo.\n 1 2\n"));
    EXPECT_DOUBLE_EQ(k.dt_s, 1.0 / hz);
  }
  // Times uneven by half a per cent of the step are refused (resampled as uniform, the record
  // would shift); decimal times' rounding (0.1 + 0.2 is not 0.3) is not.
  EXPECT_THAT(error_of([&] { read_columns(write("gm_jitter.csv", "0,1\n0.01,2\n0.02005,3\n"), AccelerationUnit::gal); }),
              HasSubstr("time steps are not uniform (near t = 0.020050 s)"));
  EXPECT_EQ(read_columns(write("gm_decimal.csv", "0.1,1\n0.2,2\n0.3,3\n0.4,4\n"), AccelerationUnit::gal).accel_m_s2.size(), 4u);
}

GroundMotionSpec kobe_spec(double start_s, double duration_s) {
  GroundMotionSpec spec;
  const char* files[] = {"RSN1106_KOBE_KJM090.AT2", "RSN1106_KOBE_KJM000.AT2", "RSN1106_KOBE_KJM-UP.AT2"};
  for (int c = 0; c < 3; ++c) {
    ComponentSpec cs;
    cs.file = kKobe / files[c];
    spec.component[c] = cs;
  }
  spec.start_s = start_s;
  spec.duration_s = duration_s;
  return spec;
}

TEST(GroundMotion, StreamRewoundToAStepIsTheStreamThatStepped) {
  // A resumed run rewinds the stream to its step: the values must be the bits it had.
  GroundMotionStream stepped(kobe_spec(5.0, 10.0), 1e-3), rewound(kobe_spec(5.0, 10.0), 1e-3);
  ASSERT_EQ(stepped.steps(), 10000);
  while (stepped.step() < 7777) stepped.advance();
  while (rewound.step() < 9000) rewound.advance();
  rewound.rewind_to(7777);
  EXPECT_EQ(rewound.step(), 7777);
  EXPECT_EQ(rewound.accel_m_s2(), stepped.accel_m_s2());
  EXPECT_EQ(rewound.velocity_m_s(), stepped.velocity_m_s());
  EXPECT_EQ(rewound.displacement_m(), stepped.displacement_m());
  EXPECT_NE(stepped.velocity_m_s(), Vec3::Zero());
}

TEST(GroundMotion, StreamsMemoryDoesNotGrowWithTheDuration) {
  const auto heap_bytes = [] {  // the arenas' and the mmapped blocks' (large vectors are mmapped)
    const struct mallinfo2 m = mallinfo2();
    return static_cast<double>(m.uordblks + m.hblkhd);
  };
  {  // AddressSanitizer's allocator (the sanitizer build, scripts/sanitize.sh) reports nothing here
    const double before = heap_bytes();
    void* volatile megabyte = std::malloc(1 << 20);  // volatile: kept, not optimised away
    const bool reported = heap_bytes() - before >= (1 << 20);
    std::free(megabyte);
    if (!reported) GTEST_SKIP() << "the allocator does not report to mallinfo2";
  }
  // A run holds its ground motion for its whole length: a table per step would be 72 B a
  // step, 108 MB for the whole Kobe record at 1e-4 s (GBs at a real model's step).
  const auto heap_with_stream = [&](double duration_s) {
    const double before = heap_bytes();
    const GroundMotionStream stream(kobe_spec(0.0, duration_s), 1e-4);
    return heap_bytes() - before;
  };
  const double one_second = heap_with_stream(1.0), whole_record = heap_with_stream(0.0);
  EXPECT_GT(whole_record, 0.0);  // the records themselves: 3 x 7,500 samples
  EXPECT_LT(whole_record, one_second + 64e3);
}

}  // namespace
}  // namespace ishibashi
