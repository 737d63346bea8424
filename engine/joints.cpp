#include "engine/joints.h"

#include <algorithm>

namespace ishibashi {

Joints find_original_joints(const State& s, const std::vector<std::uint8_t>& leave_out) {
  Joints j;
  const SubContacts& c = s.contacts;
  for (const Pair& pair : s.pairs) {
    if (!leave_out.empty() && (leave_out[pair.a] || leave_out[pair.b])) continue;
    const int begin = static_cast<int>(j.point_on_a.size());
    Vec3 centre = Vec3::Zero(), normal = Vec3::Zero();
    const Mat3 ra = s.orientation[pair.a].toRotationMatrix().transpose();  // world -> a's frame
    const Mat3 rb = s.orientation[pair.b].toRotationMatrix().transpose();
    for (int i = pair.sub_begin; i < pair.sub_begin + pair.sub_count; ++i) {
      if (!(c.flags[i] & SubContactFlag::original)) continue;
      j.point_on_a.push_back(ra * (c.point[i] - s.position[pair.a]));
      j.point_on_b.push_back(rb * (c.point[i] - s.position[pair.b]));
      centre += c.point[i];
      normal = c.normal[i];
    }
    const int count = static_cast<int>(j.point_on_a.size()) - begin;
    if (count == 0) continue;
    centre /= count;
    j.block_a.push_back(pair.a);
    j.block_b.push_back(pair.b);
    j.point_begin.push_back(begin + count);
    j.centre_on_a.push_back(ra * (centre - s.position[pair.a]));
    j.centre_on_b.push_back(rb * (centre - s.position[pair.b]));
    j.normal_on_a.push_back(ra * normal);
  }
  const std::size_t nj = j.block_a.size();
  j.reference_on_a.assign(j.point_on_a.size(), Vec3::Zero());
  j.centre_reference_on_a.assign(nj, Vec3::Zero());
  j.opening_m.assign(nj, 0.0);
  j.slip_m.assign(nj, 0.0);
  j.broken_at_reference.assign(nj, 0);
  j.bond_broken.assign(nj, 0);
  j.cracked.assign(nj, 0);
  return j;
}

namespace {

// Where b's copy of a material point is relative to a's copy, in a's principal frame, m.
Vec3 separation_on_a(const State& s, int a, int b, const Vec3& on_a, const Vec3& on_b) {
  const Mat3 ra = s.orientation[a].toRotationMatrix();
  return ra.transpose() * (s.position[b] + s.orientation[b] * on_b - s.position[a]) - on_a;
}

// Sub-contacts of the pair (a, b) that lost their bond (pairs are sorted by (a, b)).
int broken_subcontacts(const State& s, int a, int b) {
  const auto it = std::lower_bound(s.pairs.begin(), s.pairs.end(), std::pair{a, b},
                                   [](const Pair& p, const std::pair<int, int>& key) {
                                     return p.a < key.first || (p.a == key.first && p.b < key.second);
                                   });
  int broken = 0;
  if (it != s.pairs.end() && it->a == a && it->b == b)
    for (int i = it->sub_begin; i < it->sub_begin + it->sub_count; ++i)
      broken += (s.contacts.flags[i] & SubContactFlag::broken) != 0;
  return broken;
}

}  // namespace

int set_joint_reference(const State& s, Joints& j) {
  int with_broken_bond = 0;
  for (int k = 0; k < j.size(); ++k) {
    const int a = j.block_a[k], b = j.block_b[k];
    for (int q = j.point_begin[k]; q < j.point_begin[k + 1]; ++q)
      j.reference_on_a[q] = separation_on_a(s, a, b, j.point_on_a[q], j.point_on_b[q]);
    j.centre_reference_on_a[k] = separation_on_a(s, a, b, j.centre_on_a[k], j.centre_on_b[k]);
    j.broken_at_reference[k] = broken_subcontacts(s, a, b);
    with_broken_bond += j.broken_at_reference[k] > 0;
    j.bond_broken[k] = j.cracked[k] = 0;
  }
  return with_broken_bond;
}

JointCounts measure_joints(const State& s, const JointThresholds& t, Joints& j) {
  JointCounts counts;
  for (int k = 0; k < j.size(); ++k) {
    const int a = j.block_a[k], b = j.block_b[k];
    const Vec3& n = j.normal_on_a[k];
    double opening = 0;
    for (int q = j.point_begin[k]; q < j.point_begin[k + 1]; ++q)
      opening = std::max(opening, (separation_on_a(s, a, b, j.point_on_a[q], j.point_on_b[q]) - j.reference_on_a[q]).dot(n));
    const Vec3 centre = separation_on_a(s, a, b, j.centre_on_a[k], j.centre_on_b[k]) - j.centre_reference_on_a[k];
    const double slip = (centre - centre.dot(n) * n).norm();

    if (broken_subcontacts(s, a, b) > j.broken_at_reference[k]) j.bond_broken[k] = 1;

    j.opening_m[k] = opening;
    j.slip_m[k] = slip;
    const bool open = opening > t.crack_opening_m;
    if (open || j.bond_broken[k]) j.cracked[k] = 1;
    counts.open += open;
    counts.cracked += j.cracked[k];
    counts.slipped += slip > t.slip_m;
    counts.largest_opening_m = std::max(counts.largest_opening_m, opening);
    if (slip > counts.largest_slip_m) {
      counts.largest_slip_m = slip;
      counts.largest_slip_joint = k;
    }
  }
  return counts;
}

double bond_utilisation(const Model& m, const State& s, int i) {
  const SubContacts& c = s.contacts;
  if (!(c.flags[i] & SubContactFlag::bonded)) return -1;
  const PairLaw& law = m.law(m.material[c.block_a[i]], m.material[c.block_b[i]]);
  const double sigma = c.normal_spring(i) / c.area_m2[i], tau = c.shear_spring(i).norm() / c.area_m2[i];
  double share = 0;
  if (law.tensile_pa > 0) share = std::max(share, sigma / law.tensile_pa);
  if (law.cohesion_pa > 0) share = std::max(share, (tau + sigma * law.tan_friction) / law.cohesion_pa);
  return share;
}

double largest_bond_utilisation(const Model& m, const State& s) {
  double largest = -1;
  for_each_sub_contact(s, [&](int i) { largest = std::max(largest, bond_utilisation(m, s, i)); });
  return largest;
}

}  // namespace ishibashi
