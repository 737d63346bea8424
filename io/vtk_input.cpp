#include "io/vtk_input.h"

#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <stdexcept>

namespace ishibashi {

std::vector<PvdEntry> read_pvd(const std::filesystem::path& pvd) {
  if (!std::filesystem::exists(pvd)) throw std::runtime_error(pvd.string() + ": no such file");
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(pvd.c_str());
  if (parser->Parse() != 1) throw std::runtime_error(pvd.string() + ": not well-formed XML");
  vtkXMLDataElement* root = parser->GetRootElement();
  if (!root || std::string(root->GetName()) != "VTKFile" || !root->GetAttribute("type") ||
      std::string(root->GetAttribute("type")) != "Collection")
    throw std::runtime_error(pvd.string() + ": not a VTK Collection (.pvd) file");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  if (!collection) throw std::runtime_error(pvd.string() + ": no <Collection> element");
  std::vector<PvdEntry> out;
  for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = collection->GetNestedElement(i);
    double t = 0;
    const char* file = e->GetAttribute("file");
    if (!file || !e->GetScalarAttribute("timestep", t))
      throw std::runtime_error(pvd.string() + ": DataSet " + std::to_string(i) + " lacks file or timestep");
    out.push_back(PvdEntry{t, std::filesystem::absolute(pvd).parent_path() / file});
  }
  return out;
}

vtkUnstructuredGrid* read_vtu(const std::filesystem::path& vtu) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  if (!reader->CanReadFile(vtu.c_str())) throw std::runtime_error(vtu.string() + ": VTK cannot read it as .vtu");
  reader->SetFileName(vtu.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (!grid) throw std::runtime_error(vtu.string() + ": VTK read no grid");
  grid->Register(nullptr);
  return grid;
}

}  // namespace ishibashi
