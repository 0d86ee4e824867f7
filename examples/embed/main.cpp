// A host simulator embedding pbd: it owns the threads (its own tbb::task_arena), supplies wind forces every
// sub-step, adds a constraint type of its own, changes the constraints between steps, and reads the particles
// through Eigen maps without copies.
#include <pbd/io/generators.hpp>
#include <pbd/world.hpp>

#include <oneapi/tbb/task_arena.h>

#include <cstdio>

namespace host {

// The host's own constraint: keeps a particle at or above a height (an inequality, like a floor).
struct AboveHeight {
  static constexpr const char* kName = "above-height";
  static constexpr int kArity = 1;
  static constexpr bool kInequality = true;
  static constexpr bool kUnitGradients = true;
  std::array<pbd::Index, 1> particles;
  pbd::Index set;
  float z;
};
bool evaluate(const AboveHeight& c, const pbd::Vec3<float> (&p)[1], float& C, pbd::Vec3<float> (&grad)[1]) {
  C = p[0].z() - c.z;
  grad[0] = pbd::Vec3<float>::UnitZ();
  return true;
}

}  // namespace host

int main() {
  pbd::World<float> world;
  pbd::ClothOptions cloth;
  cloth.resolution = 40;
  const pbd::Index stretch = world.add_constraint_set(pbd::Stiffness::xpbd_compliance(1e-7));
  const pbd::Body body = pbd::add_cloth(world, cloth, stretch);
  const pbd::Index floor = world.add_constraint_set(pbd::Stiffness::pbd_k(1.0));
  for (pbd::Index i = 0; i < body.num_particles; ++i) world.add_custom(host::AboveHeight{{i}, floor, 0.2f});

  pbd::StepParams<float> params;
  params.substeps = 8;
  params.iterations = 2;
  world.set_params(params);
  world.set_measure_violation(true);
  world.set_force_callback([](double t, Eigen::Ref<const pbd::Matrix3X<float>> x, Eigen::Ref<pbd::Matrix3X<float>> f) {
    f.row(0).setConstant(0.002f * float(1.0 + std::sin(3.0 * t)));  // gusts of wind along +x, per particle
    (void)x;
  });

  tbb::task_arena arena(2);  // the host decides how many threads pbd may use
  arena.execute([&] {
    for (int s = 0; s < 120; ++s) {
      world.step();
      if (s == 60) world.add_stretch(0, body.num_particles - 1, stretch, 1.0f);  // tie two corners mid-run
    }
  });

  const auto x = world.positions();  // Eigen::Map: no copy, indices as the host added them
  const pbd::StepStats& st = world.last_step_stats();
  std::printf("lowest particle z = %.4f (floor 0.2), %u colors, %.3f ms last step (%.3f ms solving)\n",
              double(x.row(2).minCoeff()), st.colors, st.seconds * 1e3, st.seconds_solve * 1e3);
  for (const auto& v : st.violation)
    std::printf("  %-13s %7zu constraints, max |C| %.3g\n", v.type.c_str(), v.value.count, v.value.max);
  return x.row(2).minCoeff() >= 0.2f - 1e-4f ? 0 : 1;
}
