// Narrowphase, stage 3: contact history. Sub-contacts carry springs, bond and slip from
// step to step; a pair whose manifold is rebuilt passes them on to its new points by key,
// or failing that by proximity, keeps the spring energy it stored and its dashpots' power,
// and books the energy its springs' new forces make or lose.
#include <algorithm>
#include <cmath>

#include "engine/narrowphase.h"
#include "engine/pipeline.h"

namespace ishibashi {

int form_bonds(const Model& m, State& s) {
  SubContacts& c = s.contacts;
  int formed = 0;
  for_each_sub_contact(s, [&](int i) {
    const std::uint8_t f = c.flags[i];
    if (!(f & SubContactFlag::original) || (f & (SubContactFlag::bonded | SubContactFlag::broken))) return;
    if (!m.law(m.material[c.block_a[i]], m.material[c.block_b[i]]).carries_bond()) return;
    // Its springs keep the settled stretches (the dead load's compression and friction);
    // the bond adds strength from here on, so nothing moves when it forms.
    c.flags[i] = f | SubContactFlag::bonded;
    ++formed;
  });
  return formed;
}

// A barely moved face contact keeps its sub-contacts (keys, areas, levers, springs,
// bond) and only their geometry follows the current poses: the incident point rides on
// its block, the reference face gives the normal and the gap.
void update_in_place(State& s, const Pair& pair) {
  SubContacts& c = s.contacts;
  const int inc = pair.axis_kind == 0 ? pair.b : pair.a;
  const int f = pair.axis_feature;
  const Vec3 n = s.face_normal_world[f];
  const Vec3 normal = face_axis_normal(s, pair.axis_kind, f);
  const double d = s.face_offset_world[f];
  const Mat3& r = s.rotation[inc];
  const Vec3 x = s.position[inc];
  for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
    const Vec3 incident = x + r * c.incident_local[i];
    const double gap = n.dot(incident) - d;
    c.point[i] = incident - 0.5 * gap * n;
    c.normal[i] = normal;
    c.gap_change_m[i] = gap - c.gap_m[i];
    c.gap_m[i] = gap;
  }
}

// The relative velocity of a pair's blocks (b against a) at point p, at this step's pose
// and velocities (m/s).
Vec3 relative_velocity(const State& s, const Pair& pair, const Vec3& p) {
  const Vec3 va = s.velocity[pair.a] + s.angular_velocity[pair.a].cross(p - s.position[pair.a]);
  const Vec3 vb = s.velocity[pair.b] + s.angular_velocity[pair.b].cross(p - s.position[pair.b]);
  return vb - va;
}

// The law books each force's work over two steps (contact_law.cpp), as semi-implicit Euler
// changes the kinetic energy, F . (v + v') dt / 2: the dashpots' as this step's force and
// the last step's (SubContacts::damping_force_n), both at this step's relative velocity at
// the point; the springs' through their energy, K u^2 / 2 with u grown by this step's
// motion. A re-clipped pair's old points are gone with their last forces, which this
// books in two ways, from the relative velocities at the old points and at the new ones
// (the new ones arrive in out.damping_force_n, m/s).
// * Dashpots: the new points take over the old ones' half as a whole, the power the old
//   forces would have had at this step's velocities, shared among the new points along
//   their relative velocities. (Passing each old force on to its nearest new point booked
//   another power.) Only the balance reads the field.
// * Springs: they cannot be carried. The new springs store the old ones' energy, but their
//   forces differ, and so does their power at this step's velocities. The energy the
//   re-clip makes (J), returned: dt / 2 times the old springs' power less the new ones'. A
//   corner dug into a face, re-clipped at each step of its impact, makes an amount first
//   order in dt (Energy::reclip_j).
//   A new point without a match starts from its overlap and its normal spring takes none
//   of this step's motion (gap_change_m 0): its force does work on the stones over the
//   step, F_n v_n dt / 2, that no spring energy records, so its normal power counts the
//   other way. (Counted like a matched point's, model A dry's collapse lost 320 J at points
//   added while stones pressed into each other. A matched point whose gap change is
//   exactly 0 has no normal power either, so the test needs no flag.)
double book_reclipped_forces(const State& s, const Pair& pair, SubContacts& out, std::size_t first, std::size_t last,
                             double dt_s) {
  const SubContacts& old = s.contacts;
  double old_dashpot_power = 0, old_spring_power = 0, new_spring_power = 0;  // W
  for (int q = pair.sub_begin; q < pair.sub_begin + pair.sub_count; ++q) {
    const Vec3 v = relative_velocity(s, pair, old.point[q]);
    if (old.damping_force_n[q] != Vec3::Zero()) old_dashpot_power += old.damping_force_n[q].dot(v);
    old_spring_power += old.spring_force(q).dot(v);
  }
  double speed2 = 0;  // (m/s)^2
  for (std::size_t j = first; j < last; ++j) {
    const Vec3 v = out.damping_force_n[j];
    speed2 += v.squaredNorm();
    new_spring_power += out.spring_force(j).dot(v);
    if (out.gap_change_m[j] == 0.0) new_spring_power += 2.0 * out.normal_spring(j) * out.normal[j].dot(v);
  }
  if (old_dashpot_power == 0) {  // nothing to carry: the old dashpots open, or implicit (applied after the law)
    for (std::size_t j = first; j < last; ++j) out.damping_force_n[j] = Vec3::Zero();
  } else {
    const double scale = speed2 > 0 ? old_dashpot_power / speed2 : 0.0;  // N s/m
    for (std::size_t j = first; j < last; ++j) out.damping_force_n[j] *= scale;
  }
  return 0.5 * dt_s * (old_spring_power - new_spring_power);
}

// Writes the new manifold of a pair into `out` from `first`, each point with the history
// (springs, bond, slip) of its match among the pair's current sub-contacts. `out` grows
// by doubling, so a chunk's buffer soon stops growing at all.
double append_rebuilt(const Model& m, const State& s, const Pair& pair, const Manifold& manifold, bool first_detection,
                      double dt_s, SubContacts& out, std::size_t first) {
  const SubContacts& old = s.contacts;
  const int old_begin = pair.sub_begin, old_end = pair.sub_begin + pair.sub_count;
  const int incident_block = pair.axis_kind == 1 ? pair.a : pair.b;
  const Mat3 to_incident = s.rotation[incident_block].transpose();
  const PairLaw& law = m.law(m.material[pair.a], m.material[pair.b]);
  const bool bondable = first_detection && !m.options.bonds_when_settled && law.carries_bond();
  const double reach = 1e-2 * std::min(m.size_m[pair.a], m.size_m[pair.b]);
  const std::size_t last = first + manifold.size();
  if (out.size() < last) out.resize(std::max(last, 2 * out.size()));
  for (int i = 0; i < manifold.size(); ++i) {
    const ManifoldPoint& p = manifold.points[i];
    const std::size_t j = first + i;
    out.block_a[j] = pair.a;
    out.block_b[j] = pair.b;
    out.key[j] = p.key;
    out.point[j] = p.x;
    out.normal[j] = manifold.normal;
    out.gap_m[j] = p.gap_m;
    out.area_m2[j] = p.area_m2;
    const SpringConstants k = spring_constants(m, pair.a, pair.b, manifold.lever_a_m, manifold.lever_b_m, p.area_m2);
    out.normal_stiffness_n_m[j] = k.kn;
    out.shear_stiffness_n_m[j] = k.ks;
    out.normal_damping_n_s_m[j] = k.cn;
    out.shear_damping_n_s_m[j] = k.cs;
    out.incident_local[j] = to_incident * (p.incident - s.position[incident_block]);
    out.damping_force_n[j] = relative_velocity(s, pair, p.x);  // m/s until book_reclipped_forces
    // A key seen last step keeps its springs and bond. Failing that, the nearest old
    // point of the pair within `reach` passes them on: where corners lie exactly on
    // each other's edges (aligned masonry joints), a vertex and a pair of cuts swap
    // back and forth under round-off-sized motions, and the joint must not forget.
    // Springs pass on as stresses (scaled by the area ratio).
    int found = -1;
    for (int q = old_begin; q < old_end; ++q)
      if (old.key[q] == p.key) {
        found = q;
        break;
      }
    if (found < 0) {
      double best = reach * reach;
      for (int q = old_begin; q < old_end; ++q) {
        const double d2 = (old.point[q] - p.x).squaredNorm();
        if (d2 < best) {
          best = d2;
          found = q;
        }
      }
    }
    if (found >= 0) {
      const double ratio = p.area_m2 / old.area_m2[found];
      out.normal_stretch_m[j] = old.normal_stretch_m[found] * ratio * old.normal_stiffness_n_m[found] / k.kn;
      out.shear_stretch_m[j] = old.shear_stretch_m[found] * (ratio * old.shear_stiffness_n_m[found] / k.ks);
      out.flags[j] = old.flags[found];
      if (!(out.flags[j] & SubContactFlag::bonded))  // a dry point holds no more than its own overlap
        out.normal_stretch_m[j] = std::max(out.normal_stretch_m[j], std::min(p.gap_m, 0.0));
      // The joint's own motion over the last step, not the jump from the old point's gap
      // to the new one's (a new point is not a displacement of the joint).
      out.gap_change_m[j] = dt_s * out.damping_force_n[j].dot(manifold.normal);
      out.slip_m[j] = old.slip_m[found];
      out.bond_damage[j] = old.bond_damage[found];
    } else {
      out.normal_stretch_m[j] = bondable ? p.gap_m : std::min(p.gap_m, 0.0);  // from its overlap
      out.shear_stretch_m[j] = Vec3::Zero();
      out.flags[j] = (bondable ? SubContactFlag::bonded : 0) | (first_detection ? SubContactFlag::original : 0);
      out.gap_change_m[j] = 0.0;
      out.slip_m[j] = 0.0;
      out.bond_damage[j] = 0.0;
    }
  }
  // A re-clipped pair keeps the spring energy it stored: its springs, passed on or new,
  // are scaled together to it. Otherwise a corner contact (small area, soft) that turns
  // into a face contact (large area, stiff) would turn the stresses it passes on into
  // energy from nothing and the stones would pop apart, a face contact that turns into
  // a corner would lose most of its energy, and a pair whose features change while the
  // blocks overlap deeply (a falling stone's corner that turns out to be a face 9 mm
  // inside its neighbour) would start its new points from that overlap: a pair that
  // stored nothing starts with nothing (Nishida A at subdivision 2: balance error 50 %
  // of the energy exchanged before, 0.15 % after).
  // New points that all lie out of overlap (or none at all) store nothing: the old springs'
  // energy vanishes with them, and the re-clip books it as energy it takes.
  double before = 0, after = 0;
  for (int q = old_begin; q < old_end; ++q) before += old.spring_energy(q);
  for (std::size_t j = first; j < last; ++j) after += out.spring_energy(j);
  if (after > 0 && after != before) {
    const double scale = std::sqrt(before / after);
    for (std::size_t j = first; j < last; ++j) {
      out.normal_stretch_m[j] *= scale;
      out.shear_stretch_m[j] *= scale;
    }
  }
  const double vanished = after > 0 ? 0.0 : before;
  return book_reclipped_forces(s, pair, out, first, last, dt_s) - vanished;
}

}  // namespace ishibashi
