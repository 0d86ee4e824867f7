#include "pbd/io/frame_writer.hpp"

#include "pbd/detail/message.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <system_error>
#include <unistd.h>

namespace pbd {
namespace {

// Throws naming `what` and the item unless every index of `items` is below `n`.
template <std::size_t K>
void check_indices(const std::vector<std::array<Index, K>>& items, Index n, const std::string& what, const char* item) {
  for (std::size_t i = 0; i < items.size(); ++i)
    for (Index p : items[i])
      if (p >= n)
        throw Error(detail::message(what, ": ", item, " ", i, ": particle index ", p, " out of range (the world has ", n,
                                    " particles)"));
}

}  // namespace

template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles) {
  check_indices(triangles, world.num_particles(), "frame_topology", "triangle");
  FrameTopology t;
  t.triangles = triangles;
  std::vector<std::uint8_t> on_surface(world.num_particles(), 0);
  for (const auto& tri : triangles)
    for (Index i : tri) on_surface[i] = 1;
  for (const auto& c : world.template constraints<StretchConstraint<Real>>())
    if (!on_surface[c.particles[0]] && !on_surface[c.particles[1]]) t.lines.push_back(c.particles);
  return t;
}

template <class Real>
void write_obj_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology) {
  const std::string name = file.string();
  check_indices(topology.triangles, world.num_particles(), name, "triangle");
  check_indices(topology.lines, world.num_particles(), name, "line");
  // Written next to the file under another name, then renamed over it: a failed write leaves no half frame.
  const std::string temporary = detail::message(name, ".", ::getpid(), ".tmp");
  std::FILE* f = std::fopen(temporary.c_str(), "w");
  if (!f) throw Error(detail::message(name, ": cannot open for writing (", std::strerror(errno), ")"));
  std::fprintf(f, "# pbd frame: t = %.6f s, %u particles\n", world.time(), world.num_particles());
  const auto x = world.positions();
  for (Index i = 0; i < world.num_particles(); ++i)
    std::fprintf(f, "v %.7g %.7g %.7g\n", double(x(0, i)), double(x(1, i)), double(x(2, i)));
  for (const auto& t : topology.triangles) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
  for (const auto& l : topology.lines) std::fprintf(f, "l %u %u\n", l[0] + 1, l[1] + 1);
  const bool written = std::fflush(f) == 0 && !std::ferror(f);
  const int error = errno;
  const bool closed = std::fclose(f) == 0;
  std::error_code ec;
  if (!written || !closed) {
    std::filesystem::remove(temporary, ec);
    throw Error(detail::message(name, ": write failed (", std::strerror(written ? errno : error), ")"));
  }
  std::filesystem::rename(temporary, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw Error(detail::message(name, ": cannot replace it with the new frame (", ec.message(), ")"));
  }
}

template FrameTopology frame_topology(const World<float>&, const std::vector<std::array<Index, 3>>&);
template FrameTopology frame_topology(const World<double>&, const std::vector<std::array<Index, 3>>&);
template void write_obj_frame(const std::filesystem::path&, const World<float>&, const FrameTopology&);
template void write_obj_frame(const std::filesystem::path&, const World<double>&, const FrameTopology&);

}  // namespace pbd
