#include "io/vtk_output.h"

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cctype>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.h"
#include "io/vtk_input.h"

namespace ishibashi {

void make_vtk_ready_for_threads() { vtkObjectFactory::GetRegisteredFactories(); }

namespace {

template <class Array = vtkDoubleArray>
vtkNew<Array> vector_array(const char* name, vtkIdType n) {
  vtkNew<Array> a;
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(n);
  return a;
}

void write_grid(vtkUnstructuredGrid* grid, const std::filesystem::path& file) {
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  // Into memory, then to disk by write_text_atomically: VTK 9.1's writer, meeting a full
  // disk, returns success and leaves the file cut short, or frees an array twice and
  // crashes the run (seen with `ulimit -f`); the text writer reports why and leaves no file.
  writer->WriteToOutputStringOn();
  writer->SetInputData(grid);
  // Inline binary (base64 inside each DataArray): Debian 12's ParaView 5.11 with the
  // patched libexpat (2.5.0-1+deb12u2) fails on VTK's appended mode, raw or base64
  // ("not well-formed (invalid token)") and renders nothing. Inline files are plain XML.
  writer->SetDataModeToBinary();
  writer->SetCompressorTypeToZLib();
  // zlib's fastest level: a frame of model F in 0.13 s instead of 0.18 (its default 5),
  // 3 % larger; LZ4 took 0.08 s but 55 % more disk, which an ensemble's frames feel.
  writer->SetCompressionLevel(1);
  // VTK reports a failure (say an allocation) by an error event, printed to the terminal
  // unless observed, and may still hand back part of a file: heard here, and refused.
  std::string errors;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetClientData(&errors);
  on_error->SetCallback([](vtkObject*, unsigned long, void* heard, void* text) {
    std::string& all = *static_cast<std::string*>(heard);
    for (const char* c = text ? static_cast<const char*>(text) : "an error"; *c; ++c) {  // on one line
      if (!std::isspace(static_cast<unsigned char>(*c))) all += *c;
      else if (!all.empty() && all.back() != ' ') all += ' ';
    }
    all += "; ";
  });
  writer->AddObserver(vtkCommand::ErrorEvent, on_error);
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, on_error);
  const std::string xml = writer->Write() == 1 && errors.empty() ? writer->GetOutputString() : std::string();
  if (xml.empty())
    throw std::runtime_error("cannot write " + file.string() + ": VTK's writer failed (" +
                             (errors.empty() ? std::string("no output") : errors.substr(0, errors.size() - 2)) +
                             "; out of memory?)");
  write_text_atomically(file, xml);
}

// One polyhedron cell for block b; the points hold every block's vertices by global index.
void insert_block_cell(vtkUnstructuredGrid* grid, const Model& m, int b) {
  std::vector<vtkIdType> ids, face_stream;
  for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v) ids.push_back(v);
  for (int f = m.face_begin[b]; f < m.face_begin[b + 1]; ++f) {
    face_stream.push_back(m.face_vertex_begin[f + 1] - m.face_vertex_begin[f]);
    for (int k = m.face_vertex_begin[f]; k < m.face_vertex_begin[f + 1]; ++k) face_stream.push_back(m.face_vertex[k]);
  }
  grid->InsertNextCell(VTK_POLYHEDRON, static_cast<vtkIdType>(ids.size()), ids.data(), m.face_count(b), face_stream.data());
}

// The generator's labels of every block as cell arrays (block_id, material, part, course,
// fixed: 1 for a fixed or prescribed block), in the cells' order.
void add_block_labels(vtkUnstructuredGrid* grid, const Model& m) {
  vtkNew<vtkIntArray> block_id, material, part, course;
  block_id->SetName("block_id");
  material->SetName("material");
  part->SetName("part");
  course->SetName("course");
  vtkNew<vtkUnsignedCharArray> fixed;
  fixed->SetName("fixed");
  for (int b = 0; b < m.block_count; ++b) {
    block_id->InsertNextValue(b);
    material->InsertNextValue(m.material[b]);
    part->InsertNextValue(m.block_tag[b].part);
    course->InsertNextValue(m.block_tag[b].course);
    fixed->InsertNextValue(m.motion[b] == Motion::free ? 0 : 1);
  }
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(block_id), static_cast<vtkDataArray*>(material),
                          static_cast<vtkDataArray*>(part), static_cast<vtkDataArray*>(course),
                          static_cast<vtkDataArray*>(fixed)})
    grid->GetCellData()->AddArray(a);
}

}  // namespace

void write_modes_vtu(const Model& m, const State& s, const Eigen::MatrixXd& shapes, const std::vector<int>& free_blocks,
                     const std::filesystem::path& file) {
  const vtkIdType nv = static_cast<vtkIdType>(m.vertex_local.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nv);
  vtkNew<vtkUnstructuredGrid> grid;
  std::vector<int> group(m.block_count, -1);
  for (std::size_t g = 0; g < free_blocks.size(); ++g) group[free_blocks[g]] = static_cast<int>(g);
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (int k = 0; k < shapes.cols(); ++k) {
    arrays.push_back(vtkSmartPointer<vtkDoubleArray>::New());
    arrays.back()->SetName(("mode_" + std::to_string(k + 1)).c_str());
    arrays.back()->SetNumberOfComponents(3);
    arrays.back()->SetNumberOfTuples(nv);
  }
  for (int b = 0; b < m.block_count; ++b) {
    const Mat3 r = s.orientation[b].toRotationMatrix();
    for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v) {
      const Vec3 x = s.position[b] + r * m.vertex_local[v];
      points->SetPoint(v, x.data());
      for (int k = 0; k < shapes.cols(); ++k) {
        Vec3 d = Vec3::Zero();
        if (group[b] >= 0)
          d = shapes.col(k).segment<3>(6 * group[b]) + Vec3(shapes.col(k).segment<3>(6 * group[b] + 3)).cross(x - s.position[b]);
        arrays[k]->SetTuple(v, d.data());
      }
    }
    insert_block_cell(grid, m, b);
  }
  grid->SetPoints(points);
  for (auto& a : arrays) grid->GetPointData()->AddArray(a);
  add_block_labels(grid, m);
  write_grid(grid, file);
}

void write_blocks_vtu(const Model& m, const State& s, const std::filesystem::path& file, const Vec3& ground_displacement_m) {
  const int nb = m.block_count;
  const vtkIdType nv = static_cast<vtkIdType>(m.vertex_local.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nv);
  auto point_velocity = vector_array("velocity", nv);
  auto point_displacement = vector_array("displacement", nv);
  auto cell_velocity = vector_array("velocity", nb);
  auto cell_angular = vector_array("angular_velocity", nb);
  auto cell_displacement = vector_array("displacement", nb);
  auto cell_relative = vector_array("displacement_relative_to_ground", nb);
  vtkNew<vtkUnsignedCharArray> fallen;
  fallen->SetName("fallen");

  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(nb);
  for (int b = 0; b < nb; ++b) {
    const Mat3 r = s.orientation[b].toRotationMatrix();
    const Mat3 r0 = m.initial_orientation[b].toRotationMatrix();
    for (int v = m.vertex_begin[b]; v < m.vertex_begin[b + 1]; ++v) {
      const Vec3 x = s.position[b] + r * m.vertex_local[v];
      const Vec3 x0 = m.initial_position[b] + r0 * m.vertex_local[v];
      const Vec3 vel = s.velocity[b] + s.angular_velocity[b].cross(x - s.position[b]);
      points->SetPoint(v, x.data());
      point_velocity->SetTuple(v, vel.data());
      const Vec3 d = x - x0;
      point_displacement->SetTuple(v, d.data());
    }
    insert_block_cell(grid, m, b);
    fallen->InsertNextValue(is_fallen(m, s, b) ? 1 : 0);
    cell_velocity->SetTuple(b, s.velocity[b].data());
    cell_angular->SetTuple(b, s.angular_velocity[b].data());
    const Vec3 d = s.position[b] - m.initial_position[b];
    cell_displacement->SetTuple(b, d.data());
    const Vec3 relative = d - ground_displacement_m;
    cell_relative->SetTuple(b, relative.data());
  }
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(point_velocity);
  grid->GetPointData()->AddArray(point_displacement);
  add_block_labels(grid, m);
  grid->GetCellData()->AddArray(fallen);
  grid->GetCellData()->AddArray(cell_velocity);
  grid->GetCellData()->AddArray(cell_angular);
  grid->GetCellData()->AddArray(cell_displacement);
  grid->GetCellData()->AddArray(cell_relative);

  write_grid(grid, file);
}


void write_contacts_vtu(const Model& m, const State& s, const std::filesystem::path& file, const Joints* joints) {
  const SubContacts& c = s.contacts;
  const vtkIdType n = sub_contact_count(s);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  auto normal = vector_array("normal", n);
  // Single precision: a picture's arrows need no more, and doubles' noisy low bits made the
  // compressed frame a third larger (model A, 80 -> 110 kB).
  auto force = vector_array<vtkFloatArray>("force_n", n);
  vtkNew<vtkDoubleArray> sigma, tau, opening, slip, damage, utilisation;
  slip->SetName("slip_m");
  damage->SetName("bond_damage");  // a softening bond's lost share of strength (0 for a brittle one)
  utilisation->SetName("bond_utilisation");
  sigma->SetName("normal_stress_pa");
  tau->SetName("shear_stress_pa");
  opening->SetName("opening_m");
  vtkNew<vtkDoubleArray> joint_opening, joint_slip;
  joint_opening->SetName("joint_opening_m");
  joint_slip->SetName("joint_slip_m");
  vtkNew<vtkIntArray> state, original, block_a, block_b, joint_cracked;
  joint_cracked->SetName("joint_cracked");
  state->SetName("state");
  original->SetName("original");
  block_a->SetName("block_a");
  block_b->SetName("block_b");
  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(n);
  vtkIdType id = 0;  // the point's index in the file: the sub-contacts in pair order
  for_each_sub_contact(s, [&](int i) {
    points->SetPoint(id, c.point[i].data());
    normal->SetTuple(id, c.normal[i].data());
    const Vec3 on_b = c.spring_force(i);
    force->SetTuple3(id, on_b.x(), on_b.y(), on_b.z());
    sigma->InsertNextValue(c.normal_spring(i) / c.area_m2[i]);
    tau->InsertNextValue(c.shear_spring(i).norm() / c.area_m2[i]);
    opening->InsertNextValue(std::max(0.0, c.gap_m[i]));
    slip->InsertNextValue(c.slip_m[i]);
    damage->InsertNextValue(c.bond_damage[i]);
    const double share = bond_utilisation(m, s, i);
    utilisation->InsertNextValue(share >= 0 ? share : std::numeric_limits<double>::quiet_NaN());
    const std::uint8_t f = c.flags[i];
    const int code = (f & SubContactFlag::open)      ? 3
                     : (f & SubContactFlag::sliding) ? 2
                     : (f & SubContactFlag::bonded)  ? 0
                     : (f & SubContactFlag::broken)  ? 4
                                                     : 1;
    state->InsertNextValue(code);
    original->InsertNextValue((f & SubContactFlag::original) ? 1 : 0);
    block_a->InsertNextValue(c.block_a[i]);
    block_b->InsertNextValue(c.block_b[i]);
    if (joints) {  // joints are sorted by (block_a, block_b), as the pairs they came from
      int j = 0, hi = joints->size();
      const std::pair<int, int> key{c.block_a[i], c.block_b[i]};
      while (j < hi) {
        const int mid = (j + hi) / 2;
        if (std::pair{joints->block_a[mid], joints->block_b[mid]} < key) j = mid + 1; else hi = mid;
      }
      const bool found = j < joints->size() && joints->block_a[j] == key.first && joints->block_b[j] == key.second;
      joint_opening->InsertNextValue(found ? joints->opening_m[j] : 0.0);
      joint_slip->InsertNextValue(found ? joints->slip_m[j] : 0.0);
      joint_cracked->InsertNextValue(found ? joints->cracked[j] : 0);
    }
    grid->InsertNextCell(VTK_VERTEX, 1, &id);
    ++id;
  });
  grid->SetPoints(points);
  for (vtkDataArray* a : std::initializer_list<vtkDataArray*>{normal, force, sigma, tau, opening, slip, damage, utilisation, state, original, block_a, block_b})
    grid->GetPointData()->AddArray(a);
  if (joints)
    for (vtkDataArray* a : std::initializer_list<vtkDataArray*>{joint_opening, joint_slip, joint_cracked})
      grid->GetPointData()->AddArray(a);
  write_grid(grid, file);
}

void write_ties_vtu(const Model& m, const State& s, const std::filesystem::path& file) {
  const vtkIdType n = static_cast<vtkIdType>(m.ties.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(2 * n);
  vtkNew<vtkDoubleArray> tension, peak, plastic;
  tension->SetName("tension_n");
  peak->SetName("peak_tension_n");
  plastic->SetName("plastic_elongation_m");
  vtkNew<vtkIntArray> tie_id, block_a, block_b, yielded;
  tie_id->SetName("tie_id");
  block_a->SetName("block_a");
  block_b->SetName("block_b");
  yielded->SetName("yielded");
  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(n);
  for (vtkIdType t = 0; t < n; ++t) {
    const Tie& tie = m.ties[t];
    const Vec3 a = s.position[tie.block_a] + s.orientation[tie.block_a] * tie.anchor_a_local;
    const Vec3 b = s.position[tie.block_b] + s.orientation[tie.block_b] * tie.anchor_b_local;
    points->SetPoint(2 * t, a.data());
    points->SetPoint(2 * t + 1, b.data());
    const vtkIdType ends[2] = {2 * t, 2 * t + 1};
    grid->InsertNextCell(VTK_LINE, 2, ends);
    tension->InsertNextValue(s.tie_tension_n[t]);
    peak->InsertNextValue(s.tie_peak_tension_n[t]);
    plastic->InsertNextValue(s.tie_plastic_m[t]);
    tie_id->InsertNextValue(static_cast<int>(t));
    block_a->InsertNextValue(tie.block_a);
    block_b->InsertNextValue(tie.block_b);
    yielded->InsertNextValue(s.tie_plastic_m[t] > 0 ? 1 : 0);
  }
  grid->SetPoints(points);
  for (vtkDataArray* array : std::initializer_list<vtkDataArray*>{tie_id, block_a, block_b, tension, peak, plastic, yielded})
    grid->GetCellData()->AddArray(array);
  write_grid(grid, file);
}

void write_blocks_with_value(const std::filesystem::path& blocks_frame, const std::filesystem::path& file,
                             const std::string& name, const std::function<double(int block)>& value) {
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  grid.TakeReference(read_vtu(blocks_frame));
  vtkDataArray* block_id = grid->GetCellData()->GetArray("block_id");
  if (!block_id) throw std::runtime_error(blocks_frame.string() + ": no block_id cell array (not a blocks frame)");
  vtkNew<vtkDoubleArray> values;
  values->SetName(name.c_str());
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    values->InsertNextValue(value(static_cast<int>(block_id->GetTuple1(c))));
  grid->GetCellData()->AddArray(values);
  write_grid(grid, file);
}

}  // namespace ishibashi
