// Implicit dashpots (Damping::implicit) against closed forms: a critically damped stone
// settling on its base, converging as dt halves; a stack that settles at a step the
// study's explicit dashpots cannot take, with the energy balance closed; a launched block
// sliding the Coulomb distance; a rocking block converging to the explicit decay as dt halves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>

#include "engine/dashpot_product.h"
#include "engine/pair_damping.h"
#include "engine/world.h"
#include "geometry/demo_scenes.h"
#include "scenes.h"
#include "stone_stack.h"

namespace ishibashi {
namespace {

using test::kG;
using test::kStone;
using test::stone_stack;

// A World of `model` stepping at `share` of its own stability limit.
World world_at_share(const Model& model, double share) {
  return World(model, share * World(model, 1e-9).critical_time_step_s());
}

// A pair's 6x6 dashpot matrix against the dashpots summed one by one: for random
// sub-contacts (lever from x_a, cn, cs; the pair's one normal) and a random relative motion (v0, w), the
// force on b, -sum C_i (v0 + w x r_i) with C_i = cs I + (cn - cs) n n^T, and its moment
// about x_a are -K (v0, w).
TEST(ImplicitDamping, PairMatrixIsTheSumOfItsDashpots) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), positive(0.1, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    PairDampingSum sum;
    const Vec3 v0(u(random), u(random), u(random)), w(u(random), u(random), u(random));
    Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
    const Vec3 n = Vec3(u(random), u(random), u(random)).normalized();  // a pair's one normal
    for (int i = 0; i < 1 + trial % 6; ++i) {
      const Vec3 r(u(random), u(random), u(random));
      const double cn = 1e5 * positive(random), cs = trial % 3 == 0 ? 0.0 : 1e5 * positive(random);
      sum.add(cn, cs, r);
      const Vec3 velocity = v0 + w.cross(r);
      const Vec3 f = -(cs * velocity + (cn - cs) * velocity.dot(n) * n);
      force += f;
      moment += r.cross(f);
    }
    const Sym6 k = sum.matrix(n);
    Eigen::Matrix<double, 6, 6> full;
    for (int row = 0; row < 6; ++row)
      for (int col = 0; col < 6; ++col) full(row, col) = k.v[kSymIndex[row][col]];
    Vec6 motion, expected;
    motion << v0, w;
    expected << force, moment;
    EXPECT_LT((-(full * motion) - expected).norm(), 1e-12 * expected.norm()) << "trial " << trial;
  }
}

// Largest gap between the stone's sinking under its weight and the closed form, as a share
// of the static deflection. The stone starts touching its base, at rest; its four corner
// springs of K = E S / L_z in all (base as thick as the stone) with dashpots
// C = 2 h sqrt(M K) (MODEL.md section 3) give a bounce of omega^2 = K / M, zeta = h; with
// h = 1, critically damped: z(t) = -(M g / K) (1 - (1 + omega t) exp(-omega t)).
double worst_sinking_error(Damping damping, double steps_per_period) {
  const Material mat = test::stone(1.0);
  const double mass = mat.density_kg_m3 * kStone.prod();
  const double stiffness = mat.young_pa * kStone.x() * kStone.y() / kStone.z();
  const double omega = std::sqrt(stiffness / mass), deflection = mass * kG / stiffness;
  World w(stone_stack(1.0, damping), 2 * M_PI / omega / steps_per_period);
  const State& s = w.state();
  const double z0 = s.position[1].z();
  double worst = 0;
  while (s.time_s < 8 / omega) {
    w.step();
    const double t = s.time_s;
    const double expected = -deflection * (1 - (1 + omega * t) * std::exp(-omega * t));
    worst = std::max(worst, std::abs(s.position[1].z() - z0 - expected) / deflection);
  }
  EXPECT_EQ(s.profile.damping_unconverged, 0);
  return worst;
}

// The preconditioner's inverse (inverse_of_spd) of matrices shaped like a stone's block of
// M + dt C (masses of tonnes, inertias about a hundred kg m^2, dashpot terms from none to
// a thousand times those, coupled): D times it is the identity, it is symmetric, and it is
// Eigen's LLT inverse to round-off; a matrix with a negative eigenvalue gives NaN.
TEST(ImplicitDamping, PreconditionerInverseIsTheInverse) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), exponent(-3.0, 3.0);
  for (int trial = 0; trial < 200; ++trial) {
    Mat6 a;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) a(i, j) = u(random);
    Mat6 d = std::pow(10.0, exponent(random)) * 1000.0 * a * a.transpose();
    d.topLeftCorner<3, 3>().diagonal().array() += 2000.0;
    d.bottomRightCorner<3, 3>().diagonal().array() += 100.0 * (1.0 + u(random));
    const Mat6 inverse = inverse_of_spd(d);
    EXPECT_LT((d * inverse - Mat6::Identity()).norm(), 1e-9) << "trial " << trial;
    EXPECT_EQ((inverse - inverse.transpose()).norm(), 0.0);
    const Mat6 eigen = d.llt().solve(Mat6::Identity());
    EXPECT_LT((inverse - eigen).norm(), 1e-9 * eigen.norm()) << "trial " << trial;
  }
  Mat6 indefinite = Mat6::Identity();
  indefinite(4, 4) = -1.0;
  EXPECT_TRUE(std::isnan(inverse_of_spd(indefinite)(5, 5)));
}

TEST(ImplicitDamping, CriticallyDampedStoneSinksAsTheClosedFormAndConvergesAsDtHalves) {
  const double coarse = worst_sinking_error(Damping::implicit, 25);
  const double fine = worst_sinking_error(Damping::implicit, 50);
  const double finer = worst_sinking_error(Damping::implicit, 100);
  // 0.061, 0.020 and 0.0077 when written: backward Euler in the dashpots is first order,
  // so the error shrinks at least as fast as dt (here faster, on its way to the asymptote).
  EXPECT_LT(coarse, 0.08);
  EXPECT_LT(finer, 0.01);
  EXPECT_GT(coarse / fine, 1.8);
  EXPECT_GT(fine / finer, 1.8);
  // The explicit dashpots, where the step allows them, converge to the same curve.
  EXPECT_LT(worst_sinking_error(Damping::study, 100), 0.02);
}

// The dashpots' work on a stone riding a base that moves up and down, V0 sin(W t), in steady
// state: the joint is the critically damped oscillator of worst_sinking_error driven at its
// base, M z'' + C z' + K z = -M a_b for the stretch z, so a cycle dissipates pi C W Z^2 with
// Z = M A / |K - M W^2 + i C W| (A = V0 W, the base's acceleration). With implicit dashpots
// part of that work is booked on the base's side (the solve's pass over the prescribed
// blocks' pairs, at the end-of-step velocities), part as the stone moves. The base's work in
// and out, about 100 times what a cycle dissipates, must balance the rest step by step.
// Returns the dissipation of `cycles` cycles against the closed form, less 1, at
// `steps_per_period` steps of the joint's period.
double driven_stone_dissipation_error(Damping scheme, double steps_per_period, int cycles) {
  const Material mat = test::stone(1.0);
  const double mass = mat.density_kg_m3 * kStone.prod();
  const double stiffness = mat.young_pa * kStone.x() * kStone.y() / kStone.z();
  const double damping = 2 * std::sqrt(mass * stiffness);  // h = 1
  const double omega = std::sqrt(stiffness / mass), drive = omega / 4, base_accel = 0.5 * kG;  // never lifts off
  ModelBuilder b = test::block_on_base(kStone, mat, /*base_thickness=*/kStone.z());
  b.set_gravity(Vec3(0, 0, -kG));
  World w(b.build({.damping = scheme, .drive_fixed_blocks = true}), 2 * M_PI / omega / steps_per_period);
  State& s = w.state();
  while (s.time_s < 20 / omega) w.step();  // settled under its weight
  const double t0 = s.time_s, period = 2 * M_PI / drive;
  double damping_before = 0;
  while (s.time_s - t0 < (3 + cycles) * period) {  // three cycles for the start's transient to die
    if (damping_before == 0 && s.time_s - t0 >= 3 * period) damping_before = s.energy.damping_j;
    s.velocity[0].z() = base_accel / drive * std::sin(drive * (s.time_s - t0));
    w.step();
  }
  const double stretch = mass * base_accel / std::abs(std::complex<double>(stiffness - mass * drive * drive, damping * drive));
  const double expected = cycles * M_PI * damping * drive * stretch * stretch;
  EXPECT_EQ(s.profile.damping_unconverged, 0);
  // The ground's work with each pose's force paired one step off drifted by 30 % of the
  // dissipation, with explicit dashpots and implicit ones (tried).
  EXPECT_LT(std::abs(s.energy.balance_error_j()), 0.01 * s.energy.damping_j) << damping_name(scheme);
  return (s.energy.damping_j - damping_before) / expected - 1;
}

TEST(ImplicitDamping, DrivenStoneDissipatesAsTheClosedFormAndConvergesAsDtHalves) {
  const double coarse = driven_stone_dissipation_error(Damping::implicit, 50, 5);
  const double fine = driven_stone_dissipation_error(Damping::implicit, 100, 5);
  const double finer = driven_stone_dissipation_error(Damping::implicit, 200, 5);
  // +0.136, +0.069 and +0.035 when written: backward Euler in the dashpots, first order. The
  // base's side booked at the velocities before the solve (v*) gave -1.8 at 100 (tried).
  EXPECT_LT(std::abs(finer), 0.05);
  EXPECT_GT(coarse / fine, 1.8);
  EXPECT_GT(fine / finer, 1.8);
  // The explicit dashpots, where the step allows them, converge to the closed form too
  // (+0.053 and +0.012 when written).
  const double explicit_fine = driven_stone_dissipation_error(Damping::study, 100, 5);
  const double explicit_finer = driven_stone_dissipation_error(Damping::study, 200, 5);
  EXPECT_LT(std::abs(explicit_finer), 0.05);
  EXPECT_GT(explicit_fine / explicit_finer, 1.8);
}

// The same stone on a base that rocks about a horizontal axis through its top face,
// W0 sin(W t) below the joint's resonance: the base works on the stone through moments as
// well as forces, and the balance closes within 1 % of what the dashpots dissipate, with
// explicit dashpots and implicit ones. Without the moments' work it misses by all of it,
// and with the moments paired with this step's velocity alone by 3-4 % (tried).
TEST(ImplicitDamping, RockingBaseBalancesTheDashpotsWork) {
  for (Damping scheme : {Damping::study, Damping::implicit}) {
    const Material mat = test::stone(1.0);
    const double omega = std::sqrt(mat.young_pa * kStone.x() * kStone.y() / kStone.z() /
                                   (mat.density_kg_m3 * kStone.prod()));
    const double drive = omega / 4, turn_accel = 5.0;  // rad/s^2: the stone's edge rises 1.6 m/s^2
    ModelBuilder b = test::block_on_base(kStone, mat, /*base_thickness=*/kStone.z());
    b.set_gravity(Vec3(0, 0, -kG));
    World w(b.build({.damping = scheme, .drive_fixed_blocks = true}), 2 * M_PI / omega / 100);
    State& s = w.state();
    while (s.time_s < 20 / omega) w.step();
    const double t0 = s.time_s, damping_before = s.energy.damping_j;
    while (s.time_s - t0 < 8 * 2 * M_PI / drive) {
      s.angular_velocity[0].x() = turn_accel / drive * std::sin(drive * (s.time_s - t0));
      w.step();
    }
    const double dissipated = s.energy.damping_j - damping_before;
    ASSERT_GT(dissipated, 0.0) << damping_name(scheme);
    EXPECT_LT(std::abs(s.energy.balance_error_j()), 0.01 * dissipated) << damping_name(scheme);
  }
}

// Four stones on a base with h = 1, at 0.8 of the springs' limit: the study's explicit
// dashpots make that step unstable (the World refuses it); implicit ones settle the
// stack under its weight, nothing moves any more, and the energy balance closes.
TEST(ImplicitDamping, StackSettlesAtAStepTheExplicitDashpotsCannotTake) {
  World w = world_at_share(stone_stack(1.0, Damping::implicit, 4), 0.8);
  EXPECT_THROW(World(stone_stack(1.0, Damping::study, 4), w.dt_s()), ModelError);
  test::expect_stack_settles(w, 4);
  const State& s = w.state();
  EXPECT_EQ(s.profile.damping_unconverged, 0);
  EXPECT_GT(s.profile.damping_iterations, 0);
}

// A block launched at v0 along a flat base stops after v0^2 / (2 mu g) (Coulomb friction
// alone decelerates it), with the implicit dashpots at any step up to 0.8 of the springs'
// limit as with the explicit ones.
TEST(ImplicitDamping, LaunchedBlockSlidesTheCoulombDistance) {
  const double v0 = 0.5, phi = 33.23 * M_PI / 180, expected = v0 * v0 / (2 * std::tan(phi) * kG);
  for (Damping damping : {Damping::study, Damping::implicit})
    for (double share : {0.8, 0.4, 0.05}) {
      World w = world_at_share(test::block_on_base(Vec3(0.64, 0.64, 0.32), test::stone()).build({.damping = damping}), share);
      State& s = w.state();
      s.velocity[1] = Vec3(v0, 0, 0);
      const double x0 = s.position[1].x();
      while (s.time_s < 0.5) w.step();
      EXPECT_NEAR(s.position[1].x() - x0, expected, 0.015 * expected) << damping_name(damping) << " at " << share;
      EXPECT_LT(s.velocity[1].norm(), 1e-3);
    }
}

// A free-rocking slender block, 0.32 m wide and 0.64 m tall (alpha = 26.6 degrees),
// started rotating about its bottom edge at 1.2 rad/s (a third of the energy that tips it
// over), dashpots with h = 1, at `share` of the World's stability limit for `damping`.
constexpr double kRockWidth = 0.32, kRockHeight = 0.64, kRockSpin = 1.2;

// Closed form of the first swing (no impact yet): rigid rotation about the edge, the
// kinetic energy I_o w0^2 / 2, I_o = m (b^2 + h^2) / 3, lifts the centroid at R = the
// half-diagonal from R cos(alpha) to R cos(alpha - theta).
double rocking_first_peak() {
  const double b = kRockWidth, h = kRockHeight, radius = 0.5 * std::hypot(b, h), alpha = std::atan(b / h);
  const double lift = (b * b + h * h) / 3 * kRockSpin * kRockSpin / (2 * kG * radius);
  return alpha - std::acos(std::cos(alpha) + lift);
}

// Peak rotations (rad) of the first two half-cycles: before and after the first impact.
struct RockingPeaks {
  double first = 0, second = 0;
};
RockingPeaks rocking_peaks(Damping damping, double share) {
  const double b = kRockWidth, h = kRockHeight, omega0 = kRockSpin;
  World w = world_at_share(test::block_on_base(Vec3(b, 0.64, h), test::stone(1.0, 60.0)).build({.damping = damping}), share);
  State& s = w.state();
  s.angular_velocity[1] = Vec3(0, omega0, 0);  // about the +x bottom edge: v = w x (x_c - edge)
  s.velocity[1] = omega0 * Vec3(h / 2, 0, b / 2);
  RockingPeaks peaks;
  double peak = 0;
  int side = 0, half_cycles = 0;
  while (s.time_s < 2.0) {
    w.step();
    const Quat q = s.orientation[1] * w.model().initial_orientation[1].inverse();
    const double angle = 2 * std::atan2(q.y(), q.w());
    if (std::abs(angle) < 1e-5) continue;
    const int now = angle > 0 ? 1 : -1;
    if (side != 0 && now != side) {  // rocked over to the other edge
      if (++half_cycles == 2) {
        peaks.second = peak;
        return peaks;
      }
      peaks.first = peak;
      peak = 0;
    }
    side = now;
    peak = std::max(peak, std::abs(angle));
  }
  ADD_FAILURE() << "the block did not rock twice";
  return peaks;
}

// Rocking: the first swing, before any impact, as the closed form for both schemes at
// every step; the second, after the first impact, with implicit dashpots converges to the
// explicit scheme's at a small step as dt halves. At the default 0.4 of the springs'
// limit each impact dissipates more (the second peak about 12 % low: the implicit step is
// coarse for impacts, issue 28 item 2).
TEST(ImplicitDamping, RockingBlockConvergesToTheExplicitDecayAsDtHalves) {
  const double closed_form = rocking_first_peak();
  auto second_peak = [&](Damping damping, double share) {
    const RockingPeaks peaks = rocking_peaks(damping, share);
    EXPECT_NEAR(peaks.first, closed_form, 0.01 * closed_form) << damping_name(damping) << " at " << share;
    return peaks.second;
  };
  const double reference = second_peak(Damping::study, 0.05);
  EXPECT_NEAR(second_peak(Damping::study, 0.8), reference, 0.02 * reference);
  double last_error = 1;
  for (double share : {0.4, 0.2, 0.1, 0.05}) {
    const double error = std::abs(second_peak(Damping::implicit, share) - reference) / reference;
    EXPECT_LE(error, last_error + 1e-3) << share;
    last_error = error;
    if (share == 0.4) {
      EXPECT_LT(error, 0.15);
    }
  }
  EXPECT_LT(last_error, 0.01);
}

// A 4 x 6 stone wall of two leaves with implicit dashpots, its base shaken at 0.8 g and
// 5 Hz for 3000 steps of 3e-5 s: its joints open, close, are re-clipped and regrouped.
// check(state, step) after every `every`-th step.
template <class Check>
State shaken_wall(int every, Check&& check) {
  WallSpec spec;
  spec.courses = 4;
  spec.stones_per_course = 6;
  spec.leaves = 2;
  spec.options.damping = Damping::implicit;
  World w(make_wall_model(spec), 3e-5);
  State& s = w.state();
  for (int i = 0; i < 3000; ++i) {
    s.velocity[0].x() += 0.8 * kG * std::sin(2 * M_PI * 5.0 * s.time_s) * w.dt_s();
    w.step();
    if (i % every == 0) check(s, i);
  }
  return s;
}

// The pair matrices are summed about the pair's one normal (pair_damping.h): every
// sub-contact of a pair keeps the same normal, bit for bit, as a shaken wall's joints
// are re-clipped, updated in place and regrouped.
TEST(ImplicitDamping, EverySubContactOfAPairHasThePairsNormal) {
  int checked = 0;
  const State end = shaken_wall(100, [&](const State& s, int) {
    for (const Pair& pair : s.pairs)
      for (int k = pair.sub_begin + 1; k < pair.sub_begin + pair.sub_count; ++k, ++checked)
        ASSERT_EQ(s.contacts.normal[k], s.contacts.normal[pair.sub_begin]) << "pair " << pair.a << "-" << pair.b;
  });
  EXPECT_GT(checked, 1000);
  EXPECT_GT(end.profile.contact_regroups, 0);  // the layout changed: pairs were re-clipped
}

// A pair whose sub-contacts are all open has no dashpots (MODEL.md section 3): the contact
// law marks it for the solve to skip, and only it. In the shaken wall both kinds of pair
// with sub-contacts occur.
TEST(ImplicitDamping, SolveSkipsExactlyThePairsWhoseJointsAreAllOpen) {
  int open_pairs = 0, closed_pairs = 0;
  shaken_wall(50, [&](const State& s, int step) {
    for (std::size_t p = 0; p < s.pairs.size(); ++p) {
      const Pair& pair = s.pairs[p];
      if (pair.sub_count == 0) continue;
      bool closed = false;
      for (int k = pair.sub_begin; k < pair.sub_begin + pair.sub_count; ++k)
        closed |= !(s.contacts.flags[k] & SubContactFlag::open);
      ASSERT_EQ(s.implicit.blocks[p][1] >= 0, closed) << "pair " << pair.a << "-" << pair.b << " at step " << step;
      ++(closed ? closed_pairs : open_pairs);
    }
  });
  EXPECT_GT(open_pairs, 0);
  EXPECT_GT(closed_pairs, 0);
}

// The solve's lists of pairs with dashpots (ImplicitDamping::dashpot_pairs) are made anew
// only for the blocks of pairs whose dashpots came or went: after every step of the shaken
// wall, each block's lists are those read off the pairs, and joints opened and closed
// between steps whose pair list did not change (so the lists were kept and mended).
TEST(ImplicitDamping, DashpotListsFollowTheJointsAsTheyOpenAndClose) {
  std::vector<int> had_dashpots;
  std::vector<std::pair<int, int>> had_pairs;
  int mended_steps = 0;
  shaken_wall(1, [&](const State& s, int step) {
    const ImplicitDamping& w = s.implicit;
    for (int i = 0; i + 1 < static_cast<int>(s.block_pair_begin.size()); ++i) {
      std::vector<int> as_a, as_b;
      for (int q = s.block_pair_begin[i]; q < s.block_pair_begin[i + 1]; ++q) {
        const int p = s.block_pair[q] >> 1;
        if (w.blocks[p][1] >= 0) ((s.block_pair[q] & 1) ? as_b : as_a).push_back(p);
      }
      const int begin = dashpot_lists_begin(s, i);
      ASSERT_EQ(std::vector<int>(w.dashpot_pairs.begin() + begin, w.dashpot_pairs.begin() + w.a_end[i]), as_a)
          << "block " << i << " at step " << step;
      ASSERT_EQ(std::vector<int>(w.dashpot_pairs.begin() + w.a_end[i], w.dashpot_pairs.begin() + w.b_end[i]), as_b)
          << "block " << i << " at step " << step;
    }
    std::vector<int> has(s.pairs.size());
    std::vector<std::pair<int, int>> pairs(s.pairs.size());
    for (std::size_t p = 0; p < s.pairs.size(); ++p) has[p] = w.blocks[p][1] >= 0, pairs[p] = {s.pairs[p].a, s.pairs[p].b};
    mended_steps += pairs == had_pairs && has != had_dashpots;
    had_dashpots = has;
    had_pairs = pairs;
  });
  EXPECT_GT(mended_steps, 10);
}

// The solve's tolerance (ModelOptions::damping_solve_tolerance): from the same state, a
// wall's first step solved to 1e-2 stops in fewer iterations than one solved to 1e-10,
// and the dashpots' velocity change it finds is that one's within a few times 1e-2 (the
// residual's share bounds the error's up to the preconditioned matrix's condition).
TEST(ImplicitDamping, SolveStopsAtItsTolerance) {
  auto first_step = [](double tolerance) {
    WallSpec spec;
    spec.courses = 5;
    spec.stones_per_course = 14;
    spec.leaves = 2;
    spec.options.damping = Damping::implicit;
    spec.options.damping_solve_tolerance = tolerance;
    World w(make_wall_model(spec), 3e-5);
    w.step();
    return std::make_pair(w.state().implicit.delta, w.state().profile.damping_iterations);
  };
  const auto [reference, reference_iterations] = first_step(1e-10);
  const auto [loose, loose_iterations] = first_step(1e-2);
  EXPECT_LT(loose_iterations, reference_iterations);
  double difference2 = 0, size2 = 0;
  for (std::size_t b = 0; b < reference.size(); ++b) {
    difference2 += (loose[b] - reference[b]).squaredNorm();
    size2 += reference[b].squaredNorm();
  }
  ASSERT_GT(size2, 0);
  EXPECT_LT(std::sqrt(difference2 / size2), 0.05);
  EXPECT_GT(std::sqrt(difference2 / size2), 1e-9);  // it did stop early
}

// Backward Euler in the dashpots, from first principles: over a step each free block's new
// velocities satisfy M (v - v*) = dt F_d(v), v* what the same step gives without dashpots
// (the state's dashpot constants zeroed, explicit scheme), M its mass and its inertia
// R diag(I) R^T in the world, F_d the sum of its sub-contacts' dashpots,
// -(cn n n^T + cs (I - n n^T)) u at the relative velocity u of the two blocks' points
// there, and the moment of each about its centroid. A 0.9 x 0.5 x 0.3 m block turned 30
// degrees about z (its principal axes are not the world's) on the base, two 0.3 m blocks
// on it (it is a in two pairs with dashpots: the pair pass takes them two at a time),
// settled, then rocking and spinning. The solve runs to 1e-12 of the impulse; the residual
// is held to 1e-6 of it, as the pair matrices are single precision (the largest found: 1.2e-7).
TEST(ImplicitDamping, NewVelocitiesSolveBackwardEulerForTurnedBlocks) {
  const Mat3 turn = Eigen::AngleAxisd(M_PI / 6, Vec3::UnitZ()).toRotationMatrix();
  const double dt = 1e-5;  // s: within the explicit dashpots' limit, which the undamped world checks
  auto model = [&](Damping damping) {
    ModelBuilder b;
    const int mat = b.add_material(test::stone(1.0, 60.0));
    const Polyhedron base = make_box(Vec3(0, 0, -0.32), Vec3(4, 4, 0.64));
    b.add_block(base.vertices, base.faces, mat, Motion::fixed, "base");
    auto add = [&](const Vec3& centre, const Vec3& size) {
      const Polyhedron p = transformed(make_box(Vec3::Zero(), size), turn, turn * centre);
      b.add_block(p.vertices, p.faces, mat, Motion::free);
    };
    add(Vec3(0, 0, 0.15), Vec3(0.9, 0.5, 0.3));
    add(Vec3(0.25, 0, 0.4), Vec3(0.3, 0.3, 0.2));
    add(Vec3(-0.25, 0, 0.4), Vec3(0.3, 0.3, 0.2));
    Model m = b.build({.damping = damping});
    m.options.damping_solve_tolerance = 1e-12;
    return m;
  };
  World implicit(model(Damping::implicit), dt);
  implicit.run(400);  // settled under gravity: every joint closed and loaded
  State& s = implicit.state();
  s.velocity = {Vec3::Zero(), Vec3(0.002, -0.001, 0), Vec3(-0.001, 0.002, 0.001), Vec3(0.001, 0, -0.001)};
  s.angular_velocity = {Vec3::Zero(), Vec3(0.005, -0.003, 0.04), Vec3(-0.002, 0.004, 0.043), Vec3(0.003, 0.002, 0.037)};
  const State start = s;
  World undamped(model(Damping::study), dt);
  undamped.state() = start;
  std::fill(undamped.state().contacts.normal_damping_n_s_m.begin(), undamped.state().contacts.normal_damping_n_s_m.end(), 0.0);
  std::fill(undamped.state().contacts.shear_damping_n_s_m.begin(), undamped.state().contacts.shear_damping_n_s_m.end(), 0.0);
  implicit.step();
  undamped.step();
  const Model& m = implicit.model();
  const SubContacts& c = s.contacts;
  ASSERT_EQ(c.size(), 12u);  // the corners of each upper block's bottom face
  std::vector<Vec6> dashpots(m.block_count, Vec6::Zero());  // force, moment about the centroid
  auto point_velocity = [&](int b, const Vec3& x) {
    return Vec3(s.velocity[b] + s.angular_velocity[b].cross(x - start.position[b]));
  };
  for (std::size_t i = 0; i < c.size(); ++i) {
    ASSERT_EQ(c.flags[i] & (SubContactFlag::open | SubContactFlag::sliding | SubContactFlag::pulling), 0) << i;
    const SpringConstants k = c.constants(i);
    const Vec3& n = c.normal[i];
    const int a = c.block_a[i], b = c.block_b[i];
    const Vec3 u = point_velocity(b, c.point[i]) - point_velocity(a, c.point[i]);
    const Vec3 f = -(k.cn * n * n.dot(u) + k.cs * (u - n * n.dot(u)));  // on b
    dashpots[b] += (Vec6() << f, (c.point[i] - start.position[b]).cross(f)).finished();
    dashpots[a] -= (Vec6() << f, (c.point[i] - start.position[a]).cross(f)).finished();
  }
  const State& without = undamped.state();
  for (int b = 1; b < m.block_count; ++b) {
    SCOPED_TRACE("block " + std::to_string(b));
    const Mat3 rotation = start.orientation[b].toRotationMatrix();
    const Mat3 inertia = rotation * m.inertia_kg_m2[b].asDiagonal() * rotation.transpose();
    Vec6 impulse;
    impulse << m.mass_kg[b] * (s.velocity[b] - without.velocity[b]), inertia * (s.angular_velocity[b] - without.angular_velocity[b]);
    const Vec6 expected = dt * dashpots[b];
    EXPECT_NEAR((impulse.head<3>() - expected.head<3>()).norm(), 0.0, 1e-6 * expected.head<3>().norm());
    EXPECT_NEAR((impulse.tail<3>() - expected.tail<3>()).norm(), 0.0, 1e-6 * expected.tail<3>().norm());
    // The dashpots matter at this step: their impulse is a good share of the momentum.
    EXPECT_GT(impulse.tail<3>().norm(), 0.1 * (inertia * start.angular_velocity[b]).norm());
  }
}

}  // namespace
}  // namespace ishibashi
