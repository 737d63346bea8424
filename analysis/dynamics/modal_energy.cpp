#include "analysis/dynamics/modal_energy.h"

#include <algorithm>
#include <map>

#include "geometry/bridge.h"

namespace ishibashi {
namespace {

std::string part_label(const Model& m, int b) {
  const Part part = static_cast<Part>(m.block_tag[b].part);
  std::string label = part_name(part);
  if (m.motion[b] != Motion::free && part != Part::ground) label += " (fixed)";
  return label;
}

}  // namespace

std::vector<JointEnergyShare> modal_energy_shares(const Model& m, const State& s, const ModalResult& modal, int mode) {
  std::vector<int> group_of(m.block_count, -1);
  for (std::size_t g = 0; g < modal.free_blocks.size(); ++g) group_of[modal.free_blocks[g]] = static_cast<int>(g);
  const auto shape = modal.shapes.col(mode);
  // Displacement of the point p of block b in the mode (u + theta x r); zero for a block that does not move.
  auto displacement = [&](int b, const Vec3& p) -> Vec3 {
    const int g = group_of[b];
    if (g < 0) return Vec3::Zero();
    const Vec3 u = shape.segment<3>(6 * g), theta = shape.segment<3>(6 * g + 3);
    return u + theta.cross(p - s.position[b]);
  };

  std::vector<std::string> label(m.block_count);
  for (int b = 0; b < m.block_count; ++b) label[b] = part_label(m, b);
  std::map<std::string, JointEnergyShare> by_joint;
  double total = 0;
  const SubContacts& c = s.contacts;
  for_each_sub_contact(s, [&](int i) {
    const int a = c.block_a[i], b = c.block_b[i];
    const Vec3 du = displacement(b, c.point[i]) - displacement(a, c.point[i]);
    const Vec3& n = c.normal[i];
    const double dn = n.dot(du);
    const SpringConstants k = c.constants(i);
    const double normal = 0.5 * k.kn * dn * dn, shear = 0.5 * k.ks * (du - dn * n).squaredNorm();
    const std::string joint = label[a] < label[b] ? label[a] + " / " + label[b] : label[b] + " / " + label[a];
    JointEnergyShare& share = by_joint[joint];
    share.joint = joint;
    share.normal += normal;
    share.shear += shear;
    total += normal + shear;
  });
  std::vector<JointEnergyShare> out;
  if (!(total > 0)) return out;  // a rigid-body mode (a block touching nothing) strains no joint
  for (auto& [name, share] : by_joint) {
    share.normal /= total;
    share.shear /= total;
    out.push_back(share);
  }
  std::sort(out.begin(), out.end(), [](const JointEnergyShare& x, const JointEnergyShare& y) {
    return x.normal + x.shear > y.normal + y.shear;
  });
  return out;
}

}  // namespace ishibashi
