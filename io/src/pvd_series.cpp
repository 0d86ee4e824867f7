#include "pbd/io/pvd_series.hpp"

#include "pbd/io/atomic_file.hpp"

#include <cstdio>

namespace pbd {
namespace {

// `s` with the characters XML gives a meaning to inside a quoted attribute escaped.
std::string xml_attribute(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string pvd_text(const std::vector<PvdFrame>& frames) {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
  for (const PvdFrame& f : frames) {
    char time[40];
    std::snprintf(time, sizeof time, "%.17g", f.time);
    out += "    <DataSet timestep=\"";
    out += time;
    out += "\" part=\"0\" file=\"" + xml_attribute(f.file) + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

void write_pvd(const std::filesystem::path& file, const std::vector<PvdFrame>& frames) {
  write_file_atomically(file, pvd_text(frames));
}

}  // namespace pbd
