#include "pbd/io/frame_writer.hpp"

#include "pbd/io/atomic_file.hpp"
#include "pbd/io/finite_state.hpp"

#include <cstdio>

namespace pbd {
namespace {

// Appends printf-formatted text to `out`.
template <class... Args> void append(std::string& out, const char* format, Args... args) {
  char buffer[160];
  const int n = std::snprintf(buffer, sizeof buffer, format, args...);
  out.append(buffer, std::size_t(n));
}

// An object name for an "o" line: a byte that would end the name or the line becomes '_'.
std::string object_name(const std::string& name) {
  std::string o = name.empty() ? "body" : name;
  for (char& c : o)
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f) c = '_';
  return o;
}

}  // namespace

template <class Real> std::string obj_frame(const World<Real>& world, const FrameTopology& topology, const std::string& what) {
  check_frame_topology(topology, world.num_particles(), what);
  check_finite_state(world, what);  // "nan" in a frame is a file no OBJ loader (pbd's included) reads back
  std::string out;
  append(out, "# pbd frame: t = %.6f s, %u particles\n", world.time(), world.num_particles());
  const auto x = world.positions();
  for (const FrameBody& b : topology.bodies) {
    out += "o " + object_name(b.name) + "\n";
    for (Index i = b.first_particle; i < b.first_particle + b.num_particles; ++i)
      append(out, "v %.7g %.7g %.7g\n", double(x(0, i)), double(x(1, i)), double(x(2, i)));
    for (const auto& t : b.triangles) append(out, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    for (const auto& l : b.lines) append(out, "l %u %u\n", l[0] + 1, l[1] + 1);
    for (const auto& l : b.fiber_lines) append(out, "l %u %u\n", l[0] + 1, l[1] + 1);
  }
  return out;
}

template <class Real>
void write_obj_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology) {
  write_file_atomically(file, obj_frame(world, topology, file.string()));
}

template std::string obj_frame(const World<float>&, const FrameTopology&, const std::string&);
template std::string obj_frame(const World<double>&, const FrameTopology&, const std::string&);
template void write_obj_frame(const std::filesystem::path&, const World<float>&, const FrameTopology&);
template void write_obj_frame(const std::filesystem::path&, const World<double>&, const FrameTopology&);

}  // namespace pbd
