// sweep.csv, its rows and the curves made from them (sweep_table.h).
#include "analysis/batch/sweep_table.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "analysis/run/run_result.h"
#include "io/atomic_file.h"

namespace ishibashi {

namespace fs = std::filesystem;

namespace {

// One scenario's outcomes: (PGA, failed) of each run, in the order of the rows.
struct Outcomes {
  std::vector<double> pga;
  std::vector<int> failed;
  std::map<std::string, int> by_case;  // "record,level" -> failed
};

}  // namespace

const std::string& sweep_csv_header() {
  static const std::string header =
      "scenario,record,level,member,scale_factor,pga_g,failed," + result_csv_header() + ",host\n";
  return header;
}

std::size_t sweep_column(const std::string& name) {
  std::stringstream header(sweep_csv_header().substr(0, sweep_csv_header().size() - 1));
  std::size_t index = 0;
  for (std::string f; std::getline(header, f, ','); ++index)
    if (f == name) return index;
  throw std::logic_error("sweep.csv has no column " + name);
}

std::string scenario_name(const SweepFile& sweep, int scenario) { return sweep.scenarios[scenario].stem().string(); }

std::vector<std::string> finished_sweep_rows(const fs::path& file) {
  std::vector<std::string> rows;
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  std::size_t at = text.find('\n');  // past the header
  while (at != std::string::npos && at + 1 < text.size()) {
    const std::size_t end = text.find('\n', at + 1);
    if (end == std::string::npos) break;
    rows.push_back(text.substr(at + 1, end - at));
    at = end;
  }
  return rows;
}

std::vector<std::string> row_fields(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream s(row.substr(0, row.find('\n')));
  for (std::string f; std::getline(s, f, ',');) out.push_back(f);
  return out;
}

std::vector<ScenarioFragility> write_sweep_curves(const SweepFile& sweep, const fs::path& out, const std::vector<std::string>& rows) {
  std::map<std::string, std::vector<std::pair<double, double>>> ida;  // "scenario,record,member" -> (PGA, crown drop)
  std::map<std::string, Outcomes> outcomes;
  for (const std::string& row : rows) {
    const std::vector<std::string> f = row_fields(row);
    if (f.size() <= sweep_column("host")) continue;
    const std::string& scenario = f[sweep_column("scenario")];
    const double pga_g = std::stod(f[sweep_column("pga_g")]);
    const int failed = std::stoi(f[sweep_column("failed")]);
    const std::string& member = f[sweep_column("member")];
    ida[scenario + "," + f[sweep_column("record")] + "," + member].push_back({pga_g, std::stod(f[sweep_column("largest_crown_drop_m")])});
    Outcomes& o = outcomes[scenario];
    o.pga.push_back(pga_g);
    o.failed.push_back(failed);
    o.by_case[f[sweep_column("record")] + "," + f[sweep_column("level")] + "," + member] = failed;
  }
  std::ostringstream curves;
  curves.precision(9);
  curves << "scenario,record,member,pga_g,crown_drop_m\n";
  for (auto& [key, points] : ida) {
    std::sort(points.begin(), points.end());
    for (const auto& [x, drop] : points) curves << key << "," << x << "," << drop << "\n";
  }
  write_text_atomically(out / "ida.csv", curves.str());

  double highest_pga = 0;  // the curves reach 1.5 times the highest PGA run
  for (const auto& [name, o] : outcomes)
    for (double x : o.pga) highest_pga = std::max(highest_pga, x);
  const double top = highest_pga > 0 ? 1.5 * highest_pga : 1.0;
  std::ostringstream fits, curve, comparison;
  fits.precision(9);
  comparison.precision(9);
  fits << "scenario,median_g,beta,degenerate,outcomes,failures,log_likelihood,median_is,highest_survival_g,lowest_failure_g\n";
  curve << "scenario,pga_g,failure_probability\n";
  comparison << "scenario,reference,cases,both_stand,both_fail,only_reference_fails,only_scenario_fails,"
                "likelihood_ratio,p_same_fragility\n";
  std::vector<ScenarioFragility> result;
  const Outcomes none;  // a scenario without rows yet
  auto outcomes_of = [&](const std::string& scenario) -> const Outcomes& {
    const auto found = outcomes.find(scenario);
    return found == outcomes.end() ? none : found->second;
  };
  for (int k = 0; k < static_cast<int>(sweep.scenarios.size()); ++k) {
    ScenarioFragility r;
    r.scenario = scenario_name(sweep, k);
    const Outcomes& o = outcomes_of(r.scenario);
    r.fit = fit_lognormal_fragility(o.pga, o.failed);
    const FragilityFit& fit = r.fit;
    fits << r.scenario << "," << fit.median << "," << fit.beta << "," << (fit.degenerate ? 1 : 0) << "," << fit.outcomes
         << "," << fit.failures << "," << fit.log_likelihood << "," << median_is(fit) << "," << fit.highest_survival << ","
         << fit.lowest_failure << "\n";
    if (has_curve(fit))  // none where no run failed or every one did: any curve there would be made up
      for (int i = 1; i <= 150; ++i) curve << r.scenario << "," << top * i / 150 << "," << failure_probability(fit, top * i / 150) << "\n";
    if (k > 0) {  // against the reference, case by case (same record and level) and as curves
      r.reference = result.front().scenario;
      const Outcomes& ref = outcomes_of(r.reference);
      for (const auto& [key, failed] : o.by_case) {
        const auto other = ref.by_case.find(key);
        if (other == ref.by_case.end()) continue;
        ++r.cases;
        r.both_fail += failed && other->second;
        r.both_stand += !failed && !other->second;
        r.only_reference_fails += !failed && other->second;
        r.only_scenario_fails += failed && !other->second;
      }
      r.against_reference = compare_fragilities(ref.pga, ref.failed, o.pga, o.failed);
      comparison << r.scenario << "," << r.reference << "," << r.cases << "," << r.both_stand << "," << r.both_fail << ","
                 << r.only_reference_fails << "," << r.only_scenario_fails << "," << r.against_reference.statistic << ","
                 << r.against_reference.p_value << "\n";
    }
    result.push_back(r);
  }
  write_text_atomically(out / "fragility_fit.csv", fits.str());
  write_text_atomically(out / "fragility.csv", curve.str());
  if (sweep.scenarios.size() > 1) write_text_atomically(out / "comparison.csv", comparison.str());
  return result;
}

}  // namespace ishibashi
