#include "pbd/io/frame_writer.hpp"

#include "message.hpp"

#include <cstdio>
#include <memory>

namespace pbd {

template <class Real>
FrameTopology frame_topology(const World<Real>& world, const std::vector<std::array<Index, 3>>& triangles) {
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
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(file.string().c_str(), "w"), &std::fclose);
  if (!f) throw Error(detail::message(file.string(), ": cannot open for writing"));
  std::fprintf(f.get(), "# pbd frame: t = %.6f s, %u particles\n", world.time(), world.num_particles());
  const auto x = world.positions();
  for (Index i = 0; i < world.num_particles(); ++i)
    std::fprintf(f.get(), "v %.7g %.7g %.7g\n", double(x(0, i)), double(x(1, i)), double(x(2, i)));
  for (const auto& t : topology.triangles) std::fprintf(f.get(), "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
  for (const auto& l : topology.lines) std::fprintf(f.get(), "l %u %u\n", l[0] + 1, l[1] + 1);
  if (std::ferror(f.get())) throw Error(detail::message(file.string(), ": write failed"));
}

template FrameTopology frame_topology(const World<float>&, const std::vector<std::array<Index, 3>>&);
template FrameTopology frame_topology(const World<double>&, const std::vector<std::array<Index, 3>>&);
template void write_obj_frame(const std::filesystem::path&, const World<float>&, const FrameTopology&);
template void write_obj_frame(const std::filesystem::path&, const World<double>&, const FrameTopology&);

}  // namespace pbd
