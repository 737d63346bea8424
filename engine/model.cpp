#include "engine/model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "engine/mass_properties.h"

namespace ishibashi {

std::string Model::block_label(int b) const {
  std::ostringstream s;
  s << "block " << b;
  if (b >= 0 && b < static_cast<int>(block_name.size()) && !block_name[b].empty())
    s << " '" << block_name[b] << "'";
  return s.str();
}

namespace {
template <class E>
E parse_choice(const std::string& name, const char* what) {
  const int i = choice_index<E>(name);
  if (i < 0) throw ModelError(std::string(what) + " is \"" + name + "\"; it must be " + choice_list<E>());
  return static_cast<E>(i);
}
}  // namespace

JointRule parse_joint_rule(const std::string& name) { return parse_choice<JointRule>(name, "joint_rule"); }
ShearSpring parse_shear_spring(const std::string& name) { return parse_choice<ShearSpring>(name, "shear_spring"); }
Damping parse_damping(const std::string& name) { return parse_choice<Damping>(name, "damping"); }

PairLaw default_pair_law(const Material& a, const Material& b) {
  PairLaw law;
  law.tan_friction = std::tan(std::min(a.friction_deg, b.friction_deg) * M_PI / 180.0);
  law.tensile_pa = std::min(a.tensile_pa, b.tensile_pa);
  law.cohesion_pa = std::min(a.cohesion_pa, b.cohesion_pa);
  law.tension_fracture_j_m2 = std::min(a.tension_fracture_j_m2, b.tension_fracture_j_m2);
  law.shear_fracture_j_m2 = std::min(a.shear_fracture_j_m2, b.shear_fracture_j_m2);
  law.damping_normal = 0.5 * (a.damping_normal + b.damping_normal);
  law.damping_shear = 0.5 * (a.damping_shear + b.damping_shear);
  return law;
}

int ModelBuilder::add_material(const Material& m) {
  const std::string who = "material '" + m.name + "'";
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw ModelError(who + ": " + what);
  };
  require(m.density_kg_m3 > 0, "density_kg_m3 must be positive");
  require(m.young_pa > 0, "young_pa must be positive");
  require(m.poisson > -1.0 && m.poisson < 0.5, "poisson must lie in (-1, 0.5)");
  require(m.friction_deg >= 0 && m.friction_deg < 90, "friction_deg must lie in [0, 90)");
  require(m.tensile_pa >= 0 && m.cohesion_pa >= 0, "tensile_pa and cohesion_pa must be >= 0");
  require((m.tension_fracture_j_m2 == 0 && m.shear_fracture_j_m2 == 0) ||
              (m.tension_fracture_j_m2 > 0 && m.shear_fracture_j_m2 > 0),
          "tension_fracture_j_m2 and shear_fracture_j_m2 must be both 0 (a brittle bond) or both > 0 (a softening one)");
  require(m.damping_normal >= 0 && m.damping_shear >= 0, "damping ratios must be >= 0");
  model_.materials.push_back(m);
  return static_cast<int>(model_.materials.size()) - 1;
}

namespace {

// Newell's method: area-weighted normal of a planar or nearly planar polygon.
Vec3 newell_normal(const std::vector<Vec3>& v, const std::vector<int>& face) {
  Vec3 n = Vec3::Zero();
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Vec3& p = v[face[k]];
    const Vec3& q = v[face[(k + 1) % face.size()]];
    n += p.cross(q);
  }
  return 0.5 * n;  // |n| = area
}

using Faces = std::vector<std::vector<int>>;
using DirectedEdges = std::map<std::pair<int, int>, int>;  // (from, to) -> uses

// A block's failure: ModelError naming the block and where it is.
struct BlockError {
  std::string label;
  const std::vector<Vec3>& vertices;
  [[noreturn]] void operator()(const std::string& what) const {
    Vec3 mean = Vec3::Zero();
    for (const Vec3& v : vertices) mean += v;
    if (!vertices.empty()) mean /= static_cast<double>(vertices.size());
    std::ostringstream s;
    s << label << " (near x=" << mean.x() << " y=" << mean.y() << " z=" << mean.z() << " m): " << what;
    throw ModelError(s.str());
  }
};

// Closed and consistently oriented: every directed edge appears once, its reverse once, and
// the shell is one (V - E + F = 2). Returns the directed edges.
DirectedEdges closed_shell_edges(const std::vector<Vec3>& vertices, const Faces& faces, const BlockError& fail) {
  DirectedEdges directed;
  std::vector<int> used(vertices.size(), 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    if (face.size() < 3) fail("face " + std::to_string(f) + " has fewer than 3 corners");
    if (face.size() > kMaxFaceCorners)
      fail("face " + std::to_string(f) + " has " + std::to_string(face.size()) + " corners; at most " +
           std::to_string(kMaxFaceCorners) + " are allowed (split the face, or coarsen the block's outline)");
    for (std::size_t k = 0; k < face.size(); ++k) {
      const int u = face[k], w = face[(k + 1) % face.size()];
      if (u < 0 || u >= static_cast<int>(vertices.size()))
        fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(u) + ", which does not exist");
      used[u] = 1;
      if (++directed[{u, w}] > 1)
        fail("edge " + std::to_string(u) + "-" + std::to_string(w) + " is used twice in the same direction "
             "(faces must be counter-clockwise seen from outside, each edge shared by exactly two faces)");
    }
  }
  for (const auto& [edge, count] : directed)
    if (!directed.count({edge.second, edge.first}))
      fail("the surface is open: edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) +
           " belongs to one face only");
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!used[i]) fail("vertex " + std::to_string(i) + " belongs to no face");
  const long euler = static_cast<long>(vertices.size()) - static_cast<long>(directed.size() / 2) +
                     static_cast<long>(faces.size());
  if (euler != 2) fail("the surface is not a single closed shell (V - E + F = " + std::to_string(euler) + ", expected 2)");
  return directed;
}

// Each face's outward unit normal and plane offset (n . x); planar and non-degenerate
// within eps (m) for a block of this extent (m).
void face_planes(const std::vector<Vec3>& vertices, const Faces& faces, double eps, double extent, const BlockError& fail,
                 std::vector<Vec3>& normal, std::vector<double>& offset) {
  normal.resize(faces.size());
  offset.resize(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = newell_normal(vertices, faces[f]);
    const double area = n.norm();
    if (area < eps * extent) fail("face " + std::to_string(f) + " is degenerate (zero area)");
    normal[f] = n / area;
    offset[f] = normal[f].dot(vertices[faces[f][0]]);
    for (int v : faces[f])
      if (std::abs(normal[f].dot(vertices[v]) - offset[f]) > 1e3 * eps)
        fail("face " + std::to_string(f) + " is not planar");
  }
}

// The block's shape into the model's flat tables, in its principal frame (axes, about the
// centroid): vertices, faces, edges and their distinct directions (parallel edges share
// one, so a box has 3 and the separating-axis test needs 9 edge-edge axes, not 144).
// Returns the bounding radius about the centroid, m.
double append_shape(Model& m, const std::vector<Vec3>& vertices, const Faces& faces, const std::vector<Vec3>& normal,
                    const DirectedEdges& directed, const Mat3& axes, const Vec3& centroid) {
  const int vbase = static_cast<int>(m.vertex_local.size());
  double radius = 0.0;
  for (const Vec3& v : vertices) {
    m.vertex_local.push_back(axes.transpose() * (v - centroid));
    radius = std::max(radius, m.vertex_local.back().norm());
  }
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int v : faces[f]) m.face_vertex.push_back(vbase + v);
    m.face_vertex_begin.push_back(static_cast<int>(m.face_vertex.size()));
    const Vec3 n = axes.transpose() * normal[f];
    m.face_normal_local.push_back(n);
    m.face_offset_local.push_back(n.dot(m.vertex_local[vbase + faces[f][0]]));
  }
  const int dbase = static_cast<int>(m.direction_local.size());
  for (const auto& [edge, count] : directed) {
    if (edge.first > edge.second) continue;
    const int u = vbase + edge.first, w = vbase + edge.second;
    Vec3 d = (m.vertex_local[w] - m.vertex_local[u]).normalized();
    int found = -1;
    for (int k = dbase; k < static_cast<int>(m.direction_local.size()); ++k)
      if (d.cross(m.direction_local[k]).norm() < 1e-9) found = k;
    if (found < 0) {
      m.direction_local.push_back(d);
      found = static_cast<int>(m.direction_local.size()) - 1;
    }
    m.edge_vertex.push_back({u, w});
    m.edge_direction.push_back(found);
  }
  return radius;
}

}  // namespace

// Each check relies on the one before (a closed, consistently oriented shell before face
// normals, normals before convexity and volume, the principal frame before the tables).
int ModelBuilder::add_block(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& faces,
                            int material, Motion motion, std::string name, BlockTag tag) {
  Model& m = model_;
  const int b = m.block_count;
  std::ostringstream label;
  label << "block " << b;
  if (!name.empty()) label << " '" << name << "'";
  const BlockError fail{label.str(), vertices};

  if (material < 0 || material >= static_cast<int>(m.materials.size()))
    fail("material index " + std::to_string(material) + " is not defined");
  if (vertices.size() < 4) fail("needs at least 4 vertices, has " + std::to_string(vertices.size()));
  if (faces.size() < 4) fail("needs at least 4 faces, has " + std::to_string(faces.size()));
  for (const Vec3& v : vertices)
    if (!v.allFinite()) fail("a vertex coordinate is not a finite number");

  double extent = 0.0;
  for (const Vec3& v : vertices) extent = std::max(extent, (v - vertices[0]).norm());
  if (extent <= 0.0) fail("all vertices coincide");
  const double eps = 1e-7 * extent;

  for (std::size_t i = 0; i < vertices.size(); ++i)
    for (std::size_t j = i + 1; j < vertices.size(); ++j)
      if ((vertices[i] - vertices[j]).norm() < eps)
        fail("vertices " + std::to_string(i) + " and " + std::to_string(j) + " coincide");

  const DirectedEdges directed = closed_shell_edges(vertices, faces, fail);
  std::vector<Vec3> normal;
  std::vector<double> offset;
  face_planes(vertices, faces, eps, extent, fail, normal, offset);
  const MassProperties mp = polyhedron_mass_properties(vertices, faces);
  if (mp.volume_m3 <= 0.0)
    fail(mp.volume_m3 < 0.0 ? "faces are inside out (they must be counter-clockwise seen from outside)"
                            : "zero volume");
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t v = 0; v < vertices.size(); ++v)
      if (normal[f].dot(vertices[v]) - offset[f] > 1e3 * eps)
        fail("not convex: vertex " + std::to_string(v) + " lies outside the plane of face " + std::to_string(f));

  // Principal frame: eigenvectors of the inertia tensor, right-handed.
  const Material& mat = m.materials[material];
  const Mat3 inertia = mp.inertia_per_density * mat.density_kg_m3;
  Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia);
  Mat3 axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  const double radius = append_shape(m, vertices, faces, normal, directed, axes, mp.centroid_m);

  m.block_name.push_back(name);
  m.block_tag.push_back(tag);
  m.mass_kg.push_back(mp.volume_m3 * mat.density_kg_m3);
  m.inertia_kg_m2.push_back(eig.eigenvalues());
  m.volume_m3.push_back(mp.volume_m3);
  m.size_m.push_back(std::cbrt(mp.volume_m3));
  m.radius_m.push_back(radius);
  m.material.push_back(material);
  m.motion.push_back(motion);
  m.initial_position.push_back(mp.centroid_m);
  m.initial_orientation.push_back(Quat(axes).normalized());
  m.vertex_begin.push_back(static_cast<int>(m.vertex_local.size()));
  m.face_begin.push_back(static_cast<int>(m.face_normal_local.size()));
  m.edge_begin.push_back(static_cast<int>(m.edge_vertex.size()));
  m.direction_begin.push_back(static_cast<int>(m.direction_local.size()));
  ++m.block_count;
  return b;
}

Model ModelBuilder::build(const ModelOptions& options) const {
  Model m = model_;
  if (m.block_count == 0) throw ModelError("the model has no blocks");
  if (!m.vertex_begin.empty() && m.vertex_begin.front() != 0) throw ModelError("internal: table start");
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw ModelError("contact settings: " + what);
  };
  require(contact_.tolerance_ratio > 0 && contact_.tolerance_ratio < 0.1, "tolerance_ratio must lie in (0, 0.1)");
  require(contact_.margin_ratio > 2 * contact_.tolerance_ratio, "margin_ratio must exceed twice tolerance_ratio");
  if (options.subdivision < 1 || options.subdivision > kMaxSubdivision)
    throw ModelError("subdivision is " + std::to_string(options.subdivision) + "; it must lie in [1, " +
                     std::to_string(kMaxSubdivision) + "]");
  require(contact_.point_area_ratio > 0 && contact_.point_area_ratio <= 1, "point_area_ratio must lie in (0, 1]");
  if (!gravity_.allFinite()) throw ModelError("gravity must be finite");
  m.contact = contact_;
  m.options = options;
  if (options.drive_fixed_blocks || options.linear_joints)
    for (Motion& motion : m.motion)
      if (motion == Motion::fixed) motion = Motion::prescribed;
  double size_sum = 0.0;
  for (double size : m.size_m) size_sum += size;
  m.margin_m = contact_.margin_ratio * size_sum / m.block_count;
  double largest_free_radius = 0.0;
  for (int b = 0; b < m.block_count; ++b)
    if (m.motion[b] == Motion::free) largest_free_radius = std::max(largest_free_radius, m.radius_m[b]);
  m.apart_lever_bound_m = 6.0 * largest_free_radius + 4.0 * m.margin_m;
  m.gravity_m_s2 = gravity_;
  if (gravity_.norm() > 0) {
    const Vec3 down = gravity_.normalized();
    double deepest_immobile = -INFINITY, largest = 0.0;
    for (int b = 0; b < m.block_count; ++b) {
      largest = std::max(largest, m.size_m[b]);
      if (m.motion[b] == Motion::free) continue;
      const Mat3 r = m.initial_orientation[b].toRotationMatrix();
      for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v)
        deepest_immobile = std::max(deepest_immobile, down.dot(m.initial_position[b] + r * m.vertex_local[v]));
    }
    if (std::isfinite(deepest_immobile)) m.leave_depth_m = deepest_immobile + largest;
  }
  index_ties(m);
  if (options.linear_joints) m.gravity_m_s2 = Vec3::Zero();
  require(!(options.linear_joints && options.bonds_when_settled), "linear joints are bonded from the start");
  const std::size_t n = m.materials.size();
  m.pair_law.resize(n * n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) m.pair_law[a * n + b] = default_pair_law(m.materials[a], m.materials[b]);
  if (options.linear_joints)
    for (PairLaw& law : m.pair_law) {
      law.tensile_pa = law.cohesion_pa = 1e30;
      law.damping_normal = law.damping_shear = 0.0;
    }
  return m;
}

}  // namespace ishibashi
