// Contact law of MODEL.md section 3 for every sub-contact: normal and shear springs with
// dashpots, tension cut-off, Coulomb friction with cohesion, permanent loss of bond.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "engine/pair_damping.h"
#include "engine/parallel.h"
#include "engine/pipeline.h"

namespace ishibashi {

SpringConstants spring_constants(const Model& m, int a, int b, double lever_a_m, double lever_b_m, double area) {
  const Material& ma = m.materials[m.material[a]];
  const Material& mb = m.materials[m.material[b]];
  const PairLaw& law = m.law(m.material[a], m.material[b]);
  const double floor = 1e-6 * std::min(m.size_m[a], m.size_m[b]);
  const double la = std::max(lever_a_m, floor), lb = std::max(lever_b_m, floor);
  const double ga = ma.young_pa / (2.0 * (1.0 + ma.poisson)), gb = mb.young_pa / (2.0 * (1.0 + mb.poisson));
  SpringConstants k;
  k.kn = area / (la / ma.young_pa + lb / mb.young_pa);
  k.ks = m.options.shear_spring == ShearSpring::normal ? k.kn : area / (la / ga + lb / gb);
  const double meq = (ma.density_kg_m3 * la + mb.density_kg_m3 * lb) * area;
  k.cn = 2.0 * law.damping_normal * std::sqrt(meq * k.kn);
  k.cs = 2.0 * law.damping_shear * std::sqrt(meq * k.ks);
  return k;
}

namespace {

// Work dissipated when a spring of stiffness k, whose force was `before` last step and
// would be `trial` after this step's increment, is held at `limit` (magnitudes): the
// energy it stored above the limit, plus the limit times this step's plastic stretch.
inline double capped_work(double before, double trial, double limit, double k) {
  const double stored = std::max(std::min(before, trial), limit);
  return 0.5 * (stored * stored - limit * limit) / k + limit * (trial - stored) / k;
}

// Work dissipated by a dry shear spring of stiffness ks (N/m) that slipped over this step:
// what its force did on the joint's tangential motion vs (m/s) over the step, less what it
// stored. Its force is taken as the mean of last step's (stretch us_before, turned into this
// plane) and this step's (us_after), as semi-implicit Euler pairs a step's motion with the
// forces before and after it (F . (v + v') dt / 2: the kinetic energy's change); us_old2 is
// the squared stretch whose energy was reported last step. The force after alone times the
// plastic slip missed half the change of the limit over each step, a first-order loss where
// the normal force changes fast: a spinning stone landing on a slab, 0.9 % of the friction
// work at 2e-5 s (README, "Energy").
inline double slip_work(double ks, const Vec3& us_before, const Vec3& us_after, double us_old2, const Vec3& vs,
                        double dt) {
  return -0.5 * dt * ks * (us_before + us_after).dot(vs) - 0.5 * ks * (us_after.squaredNorm() - us_old2);
}

// An empty asm that takes x in an SSE register and may change it: GCC can then no longer
// pack two of the law's energy sums into one vector whose halves it spills and reloads
// (a 16-byte reload of two 8-byte stores waits for them: store forwarding fails). Emits
// nothing; the sums are the same numbers.
inline void in_own_register(double& x) { asm("" : "+x"(x)); }

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A softening bond is gone once this share of its strength is lost (the last 1 % of its
// fracture energy is released as a brittle bond's is).
constexpr double kBondGone = 0.99;

// A softening bond (PairLaw::bond_softens) at a sub-contact of area S: strengths
// f_t (1 - d) and c (1 - d). A trial force beyond them is held at them, and the work of
// the plastic opening or sliding raises d by work / (G_f S), mode by mode, so that the
// strength falls exponentially with the plastic displacement and the bond dissipates
// G_f S in all (Lourenco 1996's interface). Springs before: en_before (N), es_before
// (N, magnitude); after: un, en, us, es, capped in place. Returns the SubContactFlag bits
// of the modes held at their strength: pulling (tension), sliding (shear).
std::uint8_t soften_bond(const PairLaw& law, const SpringConstants& k, double area, double en_before,
                         double es_before, double& un, double& en, Vec3& us, Vec3& es, double& damage,
                         double& dissipated_j) {
  const double keep = 1.0 - damage;
  std::uint8_t capped = 0;
  double tension_work = 0.0, shear_work = 0.0;
  const double tension_limit = law.tensile_pa * keep * area;
  if (en > tension_limit) {
    tension_work = capped_work(en_before, en, tension_limit, k.kn);
    en = tension_limit;
    un = en / k.kn;
    capped |= SubContactFlag::pulling;
  }
  const double shear_limit = std::max(0.0, law.cohesion_pa * keep * area - en * law.tan_friction);
  const double es_norm = es.norm();
  if (es_norm > shear_limit) {
    shear_work = capped_work(es_before, es_norm, shear_limit, k.ks);
    const double scale = shear_limit / es_norm;
    es *= scale;
    us *= scale;
    capped |= SubContactFlag::sliding;
  }
  dissipated_j += tension_work + shear_work;
  damage = std::min(1.0, damage + tension_work / (law.tension_fracture_j_m2 * area) +
                             shear_work / (law.shear_fracture_j_m2 * area));
  return capped;
}

}  // namespace

ContactLaw::ContactLaw(const Model& m, State& s, double dt_s, bool clocked)
    : m_(m), s_(s), dt_s_(dt_s), clocked_(clocked) {
  const std::size_t np = s.pairs.size();
  s.pair_force_n.resize(np);
  s.pair_moment_nm.resize(2 * np);
  if (m.options.damping == Damping::implicit) {
    const int chunks = stage_chunks(m.block_count);  // State::pair_chunk_begin's, once the pair index follows
    s.implicit.blocks.resize(np);
    s.implicit.pair_matrix.resize(np);
    s.implicit.changed.resize(chunks);
    s.implicit.changed_count.resize(chunks, 0);
  }
}

// The hot loop of the step (about half its time): the pairs of chunk k, with each
// sub-contact's whole law inline so that its fields are read once.
void ContactLaw::run_chunk(int k) {
  const auto start = clocked_ ? Clock::now() : Clock::time_point{};
  const Model& m = m_;
  State& s = s_;
  const double dt = dt_s_;
  SubContacts& c = s.contacts;
  const bool implicit_dashpots = m.options.damping == Damping::implicit;
  // Pair pi's blocks for the solve (b = -1: no dashpots), noting a change for its lists.
  auto set_dashpot_blocks = [&s, k](std::ptrdiff_t pi, int a, int b) {
    ImplicitDamping& w = s.implicit;
    if (w.blocks[pi][1] != b) {
      int& n = w.changed_count[k];
      if (n < ImplicitDamping::kChangedPerChunk) w.changed[k][n] = static_cast<int>(pi);
      ++n;
    }
    w.blocks[pi] = {a, b};
  };
  // Pair by pair: what the sub-contacts of a pair share (blocks, velocities, law) is
  // loaded once, and their resultant is summed here so that the gather works on pairs.
  // The chunk's energy sums, J: plain locals, each kept in its own register (in_own_register).
  double elastic_j = 0, damping_j = 0, friction_j = 0, bond_j = 0;
  const std::ptrdiff_t begin = s.pair_chunk_begin[k], end = s.pair_chunk_begin[k + 1];
  for (std::ptrdiff_t pi = begin; pi < end; ++pi) {
    const Pair& pair = s.pairs[pi];
    if (pair.sub_count == 0) {
      s.pair_force_n[pi] = s.pair_moment_nm[2 * pi] = s.pair_moment_nm[2 * pi + 1] = Vec3::Zero();
      if (implicit_dashpots) set_dashpot_blocks(pi, pair.a, -1);  // no dashpots: the solve skips it
      continue;
    }
    const int a = pair.a, b = pair.b;
    // Relative velocity at r = p - x_a: v_b + w_b x (r - d) - v_a - w_a x r, d = x_b - x_a.
    const Vec3 xa = s.position[a], d = s.position[b] - xa;
    const Vec3 v0 = s.velocity[b] - s.velocity[a] - s.angular_velocity[b].cross(d);
    const Vec3 w_rel = s.angular_velocity[b] - s.angular_velocity[a];
    const PairLaw& law = m.law(m.material[a], m.material[b]);
    // 1 unless capped; 0 when implicit_damping.cpp applies the dashpots after the law.
    const double damping_scale = implicit_dashpots ? 0.0 : std::min(s.damping_scale[a], s.damping_scale[b]);
    Vec3 pair_force = Vec3::Zero(), pair_torque = Vec3::Zero();
    PairDampingSum dashpots;  // Damping::implicit: the pair's dashpots as the law leaves them
    bool closed = false;      // a sub-contact of the pair has its dashpots (is not open)
    for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
      // A dry sub-contact that was open and stays open (gap >= 0 before and after, no
      // stretch, no dashpot force) carries nothing and stores nothing: only its flags
      // change. Shaken bridges keep many such points within the contact tolerance (model
      // C dry, 10 s of Kobe: 60 % of its sub-contacts); the law below would give them the
      // same zeros.
      if (!(c.flags[i] & SubContactFlag::bonded) && c.normal_stretch_m[i] == 0 && c.gap_m[i] >= 0 &&
          c.gap_m[i] - c.gap_change_m[i] >= 0 && c.shear_stretch_m[i] == Vec3::Zero() &&
          c.damping_force_n[i] == Vec3::Zero()) {
        c.flags[i] = (c.flags[i] & (SubContactFlag::broken | SubContactFlag::original)) | SubContactFlag::open;
        continue;
      }
      const Vec3 r = c.point[i] - xa;
      const Vec3& n = c.normal[i];
      const Vec3 v_rel = v0 + w_rel.cross(r);
      const double vn = v_rel.dot(n);
      const Vec3 vs = v_rel - vn * n;
      // Dashpot work over a step is F . (v_before + v_after) / 2 dt, the form in which
      // semi-implicit Euler balances kinetic energy: last step's half is added with
      // this step's, both at this step's velocity.
      const Vec3 damping_before = c.damping_force_n[i];
      const SpringConstants k = c.constants(i);
      const double area = c.area_m2[i];
      std::uint8_t flags = c.flags[i] & (SubContactFlag::bonded | SubContactFlag::broken | SubContactFlag::original);

      // Springs as stretches u (m), e = K u, K fixed for the sub-contact's life: the
      // energy K u^2 / 2 then needs no division. Normal spring, incremental: u_n += dn,
      // dn = change of the gap (tension positive). A loaded dry spring follows the
      // joint's motion until it is unloaded, even past the geometric gap's zero (a spring
      // passed on by a re-clip may hold more than its new point's overlap: it gives that
      // energy back as work, rather than vanishing with it). An unloaded one counts only
      // the part of dn spent in overlap, so it takes up load exactly when the gap closes.
      // A new sub-contact starts from its overlap.
      const double gap = c.gap_m[i], gap_before = gap - c.gap_change_m[i];
      double un;
      if ((flags & SubContactFlag::bonded) || c.normal_stretch_m[i] < 0)
        un = c.normal_stretch_m[i] + c.gap_change_m[i];
      else
        un = std::min(gap, 0.0) - std::min(gap_before, 0.0);
      double en = k.kn * un;
      // Shear spring: turn last step's stretch into the current contact plane, keep its
      // length, then add the tangential displacement. The plane turns little in a step:
      // when the out-of-plane part is tiny, the rescale is 1 + x/2 (x = its squared
      // share), exact to 3x^2/8, with no square root.
      Vec3 us = c.shear_stretch_m[i];
      const double us_old2 = us.squaredNorm();
      const double along = us.dot(n), along2 = along * along;
      if (along2 > 0) {
        us -= along * n;
        const double in_plane2 = us_old2 - along2;
        if (along2 < 1e-16 * us_old2) {
          // 1 + x/2 rounds to 1: skip the division (most steps of a joint at rest).
        } else if (along2 < 1e-6 * us_old2)
          us *= 1.0 + 0.5 * along2 / us_old2;
        else if (in_plane2 > 0)
          us *= std::sqrt(us_old2 / in_plane2);
      }
      const Vec3 us_turned = us;  // last step's spring in this plane: its force acted over this step's motion
      us -= dt * vs;
      Vec3 es = k.ks * us;

      std::uint8_t held = 0;  // a softening bond's modes held at their strength
      if (flags & SubContactFlag::bonded) {
        bool failed;
        if (law.bond_softens()) {
          held = soften_bond(law, k, area, k.kn * c.normal_stretch_m[i], k.ks * std::sqrt(us_old2), un, en, us, es,
                             c.bond_damage[i], bond_j);
          failed = c.bond_damage[i] >= kBondGone;
        } else {  // brittle (MODEL.md section 3): gone when f_1 or f_2 reaches 0
          const double sigma = en / area, tau = es.norm() / area;
          failed = sigma - law.tensile_pa >= 0 || tau + sigma * law.tan_friction - law.cohesion_pa >= 0;
        }
        if (failed) flags = (flags & SubContactFlag::original) | SubContactFlag::broken;
      }
      const bool bonded = flags & SubContactFlag::bonded;
      Vec3 force = Vec3::Zero(), damping_force = Vec3::Zero();
      if (!bonded && un >= 0) {
        // Open: no spring, no dashpot. A bond that broke just now releases its springs'
        // energy; a dry joint's shear spring slips free (a dry gap stores nothing).
        // A brittle bond releases the mean of its springs' energy before this step and
        // now, as the elastic energy is reported: the mean over two poses (World::step).
        // The balance then closes to second order in dt; the energy now alone left half
        // the last step's change of it out (first order). A softening bond has released
        // all but a vanishing rest on its way (soften_bond).
        if (c.flags[i] & SubContactFlag::bonded) {
          const double now = 0.5 * (en * un + es.dot(us)), un_before = c.normal_stretch_m[i];
          bond_j += law.bond_softens() ? now : 0.5 * now + 0.25 * (k.kn * un_before * un_before + k.ks * us_old2);
        } else  // what the shear spring stored, less the work its last force did over this step
          friction_j += slip_work(k.ks, us_turned, Vec3::Zero(), us_old2, vs, dt);
        un = 0;
        us = Vec3::Zero();
        flags |= SubContactFlag::open;
      } else {
        Vec3 shear_damping = -(damping_scale * k.cs) * vs;
        if (!bonded) {
          const double limit = -en * law.tan_friction;
          const double es_norm2 = es.squaredNorm();
          if (es_norm2 > limit * limit) {
            const double es_norm = std::sqrt(es_norm2);
            c.slip_m[i] += (es_norm - limit) / k.ks;
            const double keep = limit / es_norm;
            us *= keep;
            es *= keep;
            friction_j += slip_work(k.ks, us_turned, us, us_old2, vs, dt);
            shear_damping = Vec3::Zero();
            flags |= SubContactFlag::sliding;
          }
        }
        // The dashpot acts while the spring is compressed, also when it pulls (a dry
        // joint leaving the base): the joint opens when the spring force reaches the
        // tensile strength (MODEL.md section 3), the linear spring-dashpot whose
        // restitution is exp(-pi zeta / sqrt(1 - zeta^2)). Cutting the pull off instead
        // gives a stone dropped with h = 1 a rebound of 0.18 of its impact speed.
        // A softening bond held at its strength has no dashpot in that direction
        // (MODEL.md: none once f_1 or f_2 reaches 0), so the strength bounds the force.
        if (held & SubContactFlag::sliding) shear_damping = Vec3::Zero();
        flags |= held;
        const double fn = en + ((held & SubContactFlag::pulling) ? 0.0 : damping_scale * k.cn * vn);
        damping_force = -(fn - en) * n + shear_damping;
        force = -fn * n + es + shear_damping;
        elastic_j += 0.5 * (en * un + es.dot(us));
      }
      c.normal_stretch_m[i] = un;
      c.shear_stretch_m[i] = us;
      if (!implicit_dashpots) {
        damping_j -= 0.5 * dt * (damping_before + damping_force).dot(v_rel);
        c.damping_force_n[i] = damping_force;
      } else if (!(flags & SubContactFlag::open)) {
        // For implicit_damping.cpp: none where the sub-contact is open, no shear dashpot
        // where it slides and no normal one where a softening bond is held at its tensile
        // strength (MODEL.md section 3).
        dashpots.add((flags & SubContactFlag::pulling) ? 0.0 : k.cn, (flags & SubContactFlag::sliding) ? 0.0 : k.cs, r);
        closed = true;
      }
      c.flags[i] = flags;
      in_own_register(elastic_j), in_own_register(damping_j);
      pair_force += force;
      pair_torque += r.cross(force);
    }
    if (implicit_dashpots) {
      // A pair whose sub-contacts are all open (half of a cracked bridge's) has a zero
      // matrix: the solve skips it, as it skips a pair without sub-contacts.
      if (closed) {
        const Sym6 k = dashpots.matrix(c.normal[pair.sub_begin]);
        Sym6f& stored = s.implicit.pair_matrix[pi];
        for (int i = 0; i < 21; ++i) stored.v[i] = static_cast<float>(k.v[i]);
      }
      set_dashpot_blocks(pi, a, closed ? b : -1);
    }
    s.pair_force_n[pi] = pair_force;
    s.pair_moment_nm[2 * pi] = -pair_torque;                         // on a, about x_a
    s.pair_moment_nm[2 * pi + 1] = pair_torque - d.cross(pair_force);  // on b, about x_b
  }
  parts_[k] = {elastic_j, damping_j, friction_j, bond_j};
  if (clocked_) chunk_s_[k] = seconds_since(start);
}

double ContactLaw::finish() {
  const auto start = clocked_ ? Clock::now() : Clock::time_point{};
  double elastic = 0;
  for (const LawEnergy& e : parts_) {
    elastic += e.elastic_j;
    s_.energy.damping_j += e.damping_j;
    s_.energy.friction_j += e.friction_j;
    s_.energy.bond_j += e.bond_j;
  }
  if (!m_.ties.empty()) elastic += apply_ties(m_, s_);
  if (clocked_) finish_s_ = seconds_since(start);
  return elastic;
}

double ContactLaw::seconds() const {
  double total = finish_s_;
  for (double t : chunk_s_) total += t;
  return total;
}

double apply_contact_law(const Model& m, State& s, double dt) {
  ContactLaw law(m, s, dt);
  parallel_ranges(s.pair_chunk_begin.data(), static_cast<int>(s.pair_chunk_begin.size()) - 1,
                  [&law](std::ptrdiff_t, std::ptrdiff_t, int k) { law.run_chunk(k); });
  return law.finish();
}

}  // namespace ishibashi
