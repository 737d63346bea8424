#include "io/paraview_state.h"

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.h"

namespace ishibashi {
namespace {

// ParaView's state format (ServerManagerState, version 5.11): proxies with numbered ids
// and the properties that differ from their defaults; ParaView fills in the rest.
class StateXml {
 public:
  StateXml() { xml_.precision(12); }
  void begin(const char* group, const char* type, int id, int servers) {
    xml_ << "    <Proxy group=\"" << group << "\" type=\"" << type << "\" id=\"" << id << "\" servers=\"" << servers << "\">\n";
    id_ = id;
  }
  void end() { xml_ << "    </Proxy>\n"; }
  template <class T>
  void values(const char* name, const std::vector<T>& v) {
    open(name, v.size());
    for (std::size_t i = 0; i < v.size(); ++i) xml_ << "<Element index=\"" << i << "\" value=\"" << v[i] << "\"/>";
    xml_ << "</Property>\n";
  }
  void value(const char* name, double v) { values(name, std::vector<double>{v}); }
  void text(const char* name, const std::string& v) { values(name, std::vector<std::string>{v}); }
  void vec(const char* name, const Vec3& v) { values(name, std::vector<double>{v.x(), v.y(), v.z()}); }
  void proxies(const char* name, const std::vector<int>& ids) {
    open(name, ids.size());
    for (int id : ids) xml_ << "<Proxy value=\"" << id << "\"/>";
    xml_ << "</Property>\n";
  }
  void input(int id) {
    open("Input", 1);
    xml_ << "<Proxy value=\"" << id << "\" output_port=\"0\"/></Property>\n";
  }
  void raw(const std::string& s) { xml_ << s; }
  std::string str() const { return xml_.str(); }

 private:
  void open(const char* name, std::size_t n) {
    xml_ << "      <Property name=\"" << name << "\" id=\"" << id_ << "." << name << "\" number_of_elements=\"" << n << "\">";
  }
  std::ostringstream xml_;
  int id_ = 0;
};

// Proxy ids; ParaView renumbers them when it loads the state.
enum Id {
  blocks_reader = 100, bridge_only, standing, fallen, contacts_reader, cracked, ties_reader,
  displacement_colours = 110,
  standing_look = 120, fallen_look, cracked_look, colour_bar, ties_look,
  render_view = 130,
  time_keeper = 140, time_cue, animation,
  layout = 150,
};

// Cells whose array `name` lies in [low, high] (cell data unless `points`).
void threshold(StateXml& x, int id, int input, const char* name, double low, double high, bool points = false) {
  x.begin("filters", "Threshold", id, 1);
  x.input(input);
  x.values("SelectInputScalars", std::vector<std::string>{"", "", "", points ? "0" : "1", name});
  x.value("LowerThreshold", low);
  x.value("UpperThreshold", high);
  x.end();
}

// A surface (or points) of `input`, coloured by the displacement table or in one colour.
void look(StateXml& x, int id, int input, const char* representation, const Vec3& colour, bool by_displacement) {
  x.begin("representations", "UnstructuredGridRepresentation", id, 21);
  x.input(input);
  x.value("Visibility", 1);
  x.text("Representation", representation);
  x.values("ColorArrayName",
           std::vector<std::string>{"", "", "", "1", by_displacement ? "displacement_relative_to_ground" : ""});
  if (by_displacement) x.proxies("LookupTable", {displacement_colours});
  x.vec("DiffuseColor", colour);
  x.vec("AmbientColor", colour);
  x.value("PointSize", 4);
  x.value("LineWidth", 3);
  x.end();
}

void collection(StateXml& x, const char* name, const std::vector<std::pair<int, const char*>>& items) {
  x.raw(std::string("    <ProxyCollection name=\"") + name + "\">\n");
  for (const auto& [id, label] : items) x.raw("      <Item id=\"" + std::to_string(id) + "\" name=\"" + label + "\"/>\n");
  x.raw("    </ProxyCollection>\n");
}

}  // namespace

void write_paraview_state(const std::filesystem::path& file, const ParaViewView& v) {
  StateXml x;
  x.raw("<?xml version=\"1.0\"?>\n<GenericParaViewApplication>\n  <ServerManagerState version=\"5.11.0\">\n");
  x.begin("sources", "PVDReader", blocks_reader, 1);
  x.text("FileName", "blocks.pvd");
  x.end();
  threshold(x, bridge_only, blocks_reader, "part", 1, 1e9);  // part 0 is the ground slab
  threshold(x, standing, bridge_only, "fallen", 0, 0);
  threshold(x, fallen, bridge_only, "fallen", 1, 1);
  x.begin("sources", "PVDReader", contacts_reader, 1);
  x.text("FileName", "contacts.pvd");
  x.end();
  threshold(x, cracked, contacts_reader, "joint_cracked", 1, 1, true);
  if (v.ties) {
    x.begin("sources", "PVDReader", ties_reader, 1);
    x.text("FileName", "ties.pvd");
    x.end();
  }

  // Viridis from 0 to the run's largest displacement of a standing stone: one scale for
  // every frame, so colours compare across time (AutomaticRescaleRangeMode -1: never).
  const double top = std::max(v.colour_range_m, 1e-6);
  std::vector<double> rgb;
  for (const auto& [at, r, g, b] : std::vector<std::array<double, 4>>{
           {0.0, 0.267, 0.005, 0.329}, {0.125, 0.283, 0.141, 0.458}, {0.25, 0.254, 0.265, 0.530},
           {0.375, 0.207, 0.372, 0.553}, {0.5, 0.164, 0.471, 0.558}, {0.625, 0.128, 0.567, 0.551},
           {0.75, 0.135, 0.659, 0.518}, {0.875, 0.478, 0.821, 0.318}, {1.0, 0.993, 0.906, 0.144}})
    rgb.insert(rgb.end(), {at * top, r, g, b});
  x.begin("lookup_tables", "PVLookupTable", displacement_colours, 21);
  x.values("RGBPoints", rgb);
  x.value("ColorSpace", 0);   // RGB, between the points above
  x.value("VectorMode", 0);   // magnitude
  x.value("AutomaticRescaleRangeMode", -1);
  x.value("ScalarRangeInitialized", 1);
  x.end();

  look(x, standing_look, standing, "Surface With Edges", Vec3(1, 1, 1), true);
  look(x, fallen_look, fallen, "Surface With Edges", Vec3(0.85, 0.1, 0.1), false);
  look(x, cracked_look, cracked, "Points", Vec3(0.05, 0.05, 0.05), false);
  if (v.ties) look(x, ties_look, ties_reader, "Wireframe", Vec3(0.1, 0.3, 0.9), false);
  x.begin("representations", "ScalarBarWidgetRepresentation", colour_bar, 21);
  x.proxies("LookupTable", {displacement_colours});
  x.text("Title", "displacement relative to the ground [m]");
  x.text("ComponentTitle", "");
  x.value("TitleFontSize", 14);
  x.value("LabelFontSize", 12);
  x.value("WindowLocation", 2);  // lower right corner
  x.value("Visibility", 1);
  x.value("Enabled", 1);
  x.end();

  // From the front left, a little above (-x, -y, +z), far enough for the whole bridge in
  // ParaView's 30 degree view angle.
  const Vec3 centre = 0.5 * (v.lower_m + v.upper_m);
  const double radius = std::max(0.5 * (v.upper_m - v.lower_m).norm(), 0.1);
  const Vec3 eye = centre + 3.0 * radius * Vec3(-0.45, -0.8, 0.4).normalized();
  x.begin("views", "RenderView", render_view, 21);
  std::vector<int> shown{standing_look, fallen_look, cracked_look, colour_bar}, timed{blocks_reader, contacts_reader};
  if (v.ties) shown.push_back(ties_look), timed.push_back(ties_reader);
  x.proxies("Representations", shown);
  x.vec("CameraPosition", eye);
  x.vec("CameraFocalPoint", centre);
  x.vec("CameraViewUp", Vec3(0, 0, 1));
  x.value("CameraParallelScale", radius);
  x.vec("CenterOfRotation", centre);
  x.value("ViewTime", v.first_time_s);
  x.values("ViewSize", std::vector<int>{1280, 720});  // pvbatch's image; the GUI sizes its own
  x.end();

  x.begin("misc", "TimeKeeper", time_keeper, 16);
  x.proxies("TimeSources", timed);
  x.proxies("Views", {render_view});
  x.value("Time", v.first_time_s);
  x.end();
  x.begin("animation", "TimeAnimationCue", time_cue, 16);
  x.proxies("AnimatedProxy", {time_keeper});
  x.text("AnimatedPropertyName", "Time");
  x.value("UseAnimationTime", 1);
  x.end();
  x.begin("animation", "AnimationScene", animation, 16);
  x.proxies("Cues", {time_cue});
  x.proxies("TimeKeeper", {time_keeper});
  x.proxies("ViewModules", {render_view});
  x.value("PlayMode", 2);  // snap to the frames' times
  x.value("StartTime", v.first_time_s);
  x.value("EndTime", v.last_time_s);
  x.value("AnimationTime", v.first_time_s);
  x.end();
  x.raw("    <Proxy group=\"misc\" type=\"ViewLayout\" id=\"" + std::to_string(layout) +
        "\" servers=\"20\">\n      <Layout number_of_elements=\"1\"><Item direction=\"0\" fraction=\"0.5\" view=\"" +
        std::to_string(render_view) + "\"/></Layout>\n    </Proxy>\n");

  collection(x, "animation", {{animation, "AnimationScene1"}, {time_cue, "TimeAnimationCue1"}});
  collection(x, "layouts", {{layout, "Layout #1"}});
  collection(x, "lookup_tables", {{displacement_colours, "displacement_relative_to_ground.PVLookupTable"}});
  std::vector<std::pair<int, const char*>> looks{{standing_look, "standing stones"}, {fallen_look, "fallen stones"},
                                                 {cracked_look, "cracked joints"}, {colour_bar, "ScalarBarWidgetRepresentation1"}};
  std::vector<std::pair<int, const char*>> sources{{blocks_reader, "blocks.pvd"}, {bridge_only, "bridge (ground slab hidden)"},
                                                   {standing, "standing stones"}, {fallen, "fallen stones"},
                                                   {contacts_reader, "contacts.pvd"}, {cracked, "cracked joints"}};
  if (v.ties) looks.push_back({ties_look, "tie rods"}), sources.push_back({ties_reader, "ties.pvd"});
  collection(x, "representations", looks);
  collection(x, "scalar_bars", {{colour_bar, "ScalarBarWidgetRepresentation1"}});
  collection(x, "sources", sources);
  collection(x, "timekeeper", {{time_keeper, "TimeKeeper1"}});
  collection(x, "views", {{render_view, "RenderView1"}});
  x.raw("  </ServerManagerState>\n</GenericParaViewApplication>\n");
  write_text_atomically(file, x.str());
}

}  // namespace ishibashi
