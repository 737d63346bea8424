// Recorded ground motions' files (io/ground_motion.h): PEER NGA .AT2, K-NET/KiK-net ASCII
// and plain columns, each read into a Record in m/s^2, with errors that name the file,
// the line and what it should hold.
#include "io/ground_motion.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ishibashi {
namespace {


[[noreturn]] void fail(const std::filesystem::path& file, int line, const std::string& what) {
  std::ostringstream s;
  s << file.string();
  if (line > 0) s << ":" << line;
  s << ": " << what;
  throw InputError(s.str());
}

std::ifstream open(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in && !std::filesystem::exists(file))  // most often a scenario copied away from its ../data
    fail(file.lexically_normal(), 0,
         "no such ground-motion file (a scenario's paths start at its own folder: with a scenario copied elsewhere "
         "copy the data folder it names too, or give an absolute path)");
  if (!in) fail(file, 0, "cannot open the ground-motion file (can this user read it?)");
  return in;
}

// True when the whole of `text` is one finite number (then in `value`).
bool parse_finite(const std::string& text, double& value) {
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && std::isfinite(value);
}

// Appends every whitespace-separated number of a line to `out`; false at the first word
// that is not a number (then in `bad`).
bool row_of_numbers(const std::string& line, std::vector<double>& out, std::string& bad) {
  std::istringstream s(line);
  double v = 0;
  while (s >> bad) {
    if (!parse_finite(bad, v)) return false;
    out.push_back(v);
  }
  return true;
}

// The same, a word that is not a number an error naming the line.
void numbers_of(const std::filesystem::path& file, int line_no, const std::string& line, std::vector<double>& out) {
  std::string bad;
  if (!row_of_numbers(line, out, bad)) fail(file, line_no, "'" + bad + "' is not a number");
}

// The number of the first line after `line_no` that is a row of numbers (commas as
// spaces), read on from `in`; 0 if none within 1,000 lines. Where a header ends.
int first_row_of_numbers(std::istream& in, int line_no) {
  std::string line, bad;
  std::vector<double> row;
  for (int n = line_no + 1; n <= line_no + 1000 && std::getline(in, line); ++n) {
    std::replace(line.begin(), line.end(), ',', ' ');
    row.clear();
    if (row_of_numbers(line, row, bad) && !row.empty()) return n;
  }
  return 0;
}

// A header number: an error naming the line and what it should hold (std::stod would
// throw a bare "stod").
double header_number(const std::filesystem::path& file, int line_no, const std::string& text, const std::string& what) {
  double v = 0;
  if (!parse_finite(text, v)) fail(file, line_no, "'" + text + "' is not a number: expected " + what);
  return v;
}

// The run of digits and points that ends just before `pos` / starts at `pos` of a line.
std::string digits_before(const std::string& line, std::size_t pos) {
  std::size_t begin = pos;
  while (begin > 0 && (std::isdigit(static_cast<unsigned char>(line[begin - 1])) || line[begin - 1] == '.')) --begin;
  return line.substr(begin, pos - begin);
}
std::string digits_from(const std::string& line, std::size_t pos) {
  std::size_t end = pos;
  while (end < line.size() && (std::isdigit(static_cast<unsigned char>(line[end])) || line[end] == '.')) ++end;
  return line.substr(pos, end - pos);
}

// The two numbers of "NPTS = n, DT = dt SEC" (any case, anywhere in the line), read by
// hand: std::regex's backtracking recurses once per character of a long damaged line.
bool at2_header_fields(const std::string& line, std::string& npts, std::string& dt) {
  std::string upper = line;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  std::size_t i = 0;
  auto spaces = [&] {
    while (i < upper.size() && std::isspace(static_cast<unsigned char>(upper[i]))) ++i;
  };
  auto word = [&](const std::string& w) {
    spaces();
    if (upper.compare(i, w.size(), w) != 0) return false;
    i += w.size();
    return true;
  };
  auto run_of = [&](const std::string& chars) {
    spaces();
    const std::size_t begin = i;
    while (i < upper.size() && chars.find(upper[i]) != std::string::npos) ++i;
    return line.substr(begin, i - begin);
  };
  for (std::size_t at = upper.find("NPTS"); at != std::string::npos; at = upper.find("NPTS", at + 1)) {
    i = at + 4;
    if (!word("=")) continue;
    npts = run_of("0123456789");
    if (npts.empty() || !word(",") || !word("DT") || !word("=")) continue;
    dt = run_of("0123456789.E+-");
    if (!dt.empty() && word("SEC")) return true;
  }
  return false;
}

double unit_factor(AccelerationUnit u) {
  switch (u) {
    case AccelerationUnit::g: return kStandardGravity_m_s2;
    case AccelerationUnit::gal: return 0.01;
    case AccelerationUnit::m_s2: return 1.0;
  }
  return 1.0;
}

}  // namespace

double Record::peak_m_s2() const {
  double p = 0;
  for (double a : accel_m_s2) p = std::max(p, std::abs(a));
  return p;
}

Record read_at2(const std::filesystem::path& file) {
  std::ifstream in = open(file);
  std::string line;
  int line_no = 0;
  std::string units;
  for (int k = 0; k < 4; ++k) {
    if (!std::getline(in, line)) fail(file, line_no, "the AT2 header is incomplete (4 lines expected)");
    ++line_no;
    if (k == 2) units = line;
  }
  std::string npts_text, dt_text;
  if (!at2_header_fields(line, npts_text, dt_text)) fail(file, 4, "expected 'NPTS = n, DT = dt SEC' in the AT2 header");
  const double npts_read = header_number(file, 4, npts_text, "the number of points NPTS");
  if (npts_read > 1e9) fail(file, 4, "NPTS = " + npts_text + " is beyond any record (at most 10^9 points)");
  const long npts = static_cast<long>(npts_read);
  Record r;
  r.source = file.filename().string();
  r.dt_s = header_number(file, 4, dt_text, "the time step DT in seconds");
  if (r.dt_s <= 0 || npts <= 1) fail(file, 4, "NPTS must exceed 1 and DT must be positive");
  std::string upper = units;
  std::transform(upper.begin(), upper.end(), upper.begin(), ::toupper);
  const double factor = upper.find("UNITS OF G") != std::string::npos ? kStandardGravity_m_s2
                        : upper.find("CM/S") != std::string::npos ? 0.01
                                                                  : 0.0;
  if (factor == 0.0) fail(file, 3, "unknown acceleration units (expected 'UNITS OF G' or 'CM/S/S')");
  while (std::getline(in, line)) {
    ++line_no;
    numbers_of(file, line_no, line, r.accel_m_s2);
  }
  if (static_cast<long>(r.accel_m_s2.size()) != npts)
    fail(file, 0, "the header says NPTS = " + std::to_string(npts) + " but the file holds " +
                      std::to_string(r.accel_m_s2.size()) + " values");
  for (double& a : r.accel_m_s2) a *= factor;
  return r;
}

Record read_knet(const std::filesystem::path& file) {
  std::ifstream in = open(file);
  std::string line;
  int line_no = 0;
  double frequency = 0, scale = 0;
  bool data = false;
  Record r;
  r.source = file.filename().string();
  while (std::getline(in, line)) {
    ++line_no;
    if (!data) {
      // Read by hand rather than by std::regex, whose backtracking recurses once per
      // character and could overflow the stack on a long damaged line.
      static const std::string frequency_label = "Sampling Freq(Hz)";
      if (line.rfind(frequency_label, 0) == 0) {
        // The label itself holds "Hz", so rfind always finds one; at or before the label's
        // end, the value has none.
        const std::size_t label = frequency_label.size(), hz = line.rfind("Hz");
        std::size_t end = hz;
        while (end > label && line[end - 1] == ' ') --end;  // "100 Hz" as well as "100Hz"
        if (hz <= label || end == label) fail(file, line_no, "cannot read the sampling frequency (expected like '100Hz')");
        frequency = header_number(file, line_no, digits_before(line, end), "the sampling frequency in Hz");
      } else if (line.rfind("Scale Factor", 0) == 0) {
        const std::size_t gal = line.find("(gal)/");
        if (gal == std::string::npos) fail(file, line_no, "cannot read the scale factor (expected like '7845(gal)/8223790')");
        const std::string what = "the scale factor like '7845(gal)/8223790'";
        const double numerator = header_number(file, line_no, digits_before(line, gal), what);
        const double denominator = header_number(file, line_no, digits_from(line, gal + 6), what);
        if (denominator <= 0) fail(file, line_no, "the scale factor's divisor must be positive");
        scale = numerator / denominator;
      } else if (line.rfind("Memo.", 0) == 0) {
        data = true;
      }
      continue;
    }
    numbers_of(file, line_no, line, r.accel_m_s2);
  }
  if (!data) fail(file, 0, "no 'Memo.' line: not a K-NET/KiK-net ASCII file");
  if (frequency <= 0) fail(file, 0, "missing 'Sampling Freq(Hz)' in the header");
  if (scale <= 0) fail(file, 0, "missing 'Scale Factor' in the header");
  if (r.accel_m_s2.size() < 2) fail(file, 0, "no data after the header");
  r.dt_s = 1.0 / frequency;
  double mean = 0;
  for (double& a : r.accel_m_s2) mean += (a *= scale * 0.01);  // counts -> gal -> m/s^2
  mean /= static_cast<double>(r.accel_m_s2.size());
  for (double& a : r.accel_m_s2) a -= mean;  // K-NET counts carry an offset
  return r;
}

Record read_columns(const std::filesystem::path& file, AccelerationUnit unit, const ColumnLayout& layout) {
  std::ifstream in = open(file);
  std::string line;
  int line_no = 0;
  Record r;
  r.source = file.filename().string();
  std::vector<double> times;
  const bool timed = layout.dt_s <= 0;
  // Values a row holds: the layout's, or, where a column is chosen, the first row's.
  std::size_t width = layout.column > 0 ? 0 : timed ? 2 : 1;
  std::vector<double> v;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no <= layout.header_lines) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    v.clear();
    std::string bad;
    if (!row_of_numbers(line, v, bad)) {
      std::string what = "'" + bad + "' is not a number";
      if (r.accel_m_s2.empty())  // before the first sample: a header, which the setting named skips
        if (const int samples = first_row_of_numbers(in, line_no))
          what += " (a header? header_lines = " + std::to_string(samples - 1) + " skips it: the samples start on line " +
                  std::to_string(samples) + ")";
      fail(file, line_no, what);
    }
    if (width == 0) {  // the first row of a chosen column
      if (timed && layout.column == 1)
        fail(file, line_no, "column 1 holds the time; the acceleration's column is 2 or more (or give dt_s)");
      width = v.size();
      if (width < static_cast<std::size_t>(layout.column))
        fail(file, line_no, std::to_string(width) + " values, so no column " + std::to_string(layout.column) + " (counted from 1)");
    }
    if (v.size() != width) {
      if (layout.column > 0)
        fail(file, line_no, std::to_string(v.size()) + " values where the first row has " + std::to_string(width));
      fail(file, line_no, std::string(timed ? "expected two columns: time (s) and acceleration" :
                                              "expected one column (acceleration) since dt_s is given") +
                              "; of a file of several columns, column = N reads one");
    }
    if (timed) times.push_back(v[0]);
    r.accel_m_s2.push_back(v[layout.column > 0 ? layout.column - 1 : width - 1]);
  }
  if (r.accel_m_s2.size() < 2) fail(file, 0, "fewer than two samples");
  if (!timed) {
    r.dt_s = layout.dt_s;
  } else {
    r.dt_s = times[1] - times[0];
    for (std::size_t i = 1; i < times.size(); ++i)
      if (std::abs(times[i] - times[i - 1] - r.dt_s) > 1e-6 * r.dt_s + 1e-9)
        fail(file, 0, "time steps are not uniform (near t = " + std::to_string(times[i]) + " s)");
    if (r.dt_s <= 0) fail(file, 0, "times must increase");
  }
  for (double& a : r.accel_m_s2) a *= unit_factor(unit);
  return r;
}

}  // namespace ishibashi
