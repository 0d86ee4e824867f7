// The peer (Bender et al., PositionBasedDynamics, MIT) on its own BarDemo bar, without the GUI: the set-up of
// Demos/BarDemo/main.cpp (its mesh read from make_bar.py's file and checked against the peer's addRegularTetModel,
// 1 kg per vertex, the i = 0 end pinned, the time step 0.005 s), with the solid method "FEM based XPBD" (3: one
// XPBD_FEMTetConstraint per tet, Young's modulus E = 1e6 and Poisson's ratio 0.3, as the demo sets for method 3) or
// "Shape Matching" (5: one ShapeMatchingConstraint per tet, stiffness 1, as the demo), stepped by the peer's own
// TimeStepController as the demo steps it, and one line of JSON as pbd_bar prints (bar_common.hpp).
// Built only with PBD_PEER_DIR (bench/peer/CMakeLists.txt), against the peer's sources compiled directly.
#include "bar_common.hpp"
#include "peer_simulation.hpp"

#include "Common/Common.h"
#include "Simulation/Constraints.h"
#include "Simulation/Simulation.h"
#include "Simulation/SimulationModel.h"
#include "Simulation/TimeManager.h"
#include "Simulation/TimeStepController.h"
#include "Utils/Logger.h"
#include "Utils/Timing.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

// The static members the peer's demos define in DemoBase.cpp.
INIT_LOGGING
INIT_TIMING

using namespace PBD;
using peer_bench::Clock;

namespace {

// The peer's own BarDemo bar, for checking that make_bar.py wrote the same mesh (positions bit for bit, the same
// tets in the same order, 1 kg per vertex).
void check_against_peer_bar(const peer_bench::Bar& b) {
  SimulationModel bar;
  bar.init();
  bar.addRegularTetModel(b.width, b.height, b.depth,
                         Vector3r(b.translation[0], b.translation[1], b.translation[2]), Matrix3r::Identity(),
                         Vector3r(b.size[0], b.size[1], b.size[2]));
  const ParticleData& pd = bar.getParticles();
  if (pd.size() != b.x.size()) throw std::runtime_error("mesh check: vertex count differs from the peer's bar");
  for (unsigned i = 0; i < pd.size(); ++i) {
    for (int d = 0; d < 3; ++d)
      if (pd.getPosition(i)[d] != b.x[i][d])
        throw std::runtime_error("mesh check: vertex " + std::to_string(i) + " differs from the peer's bar");
    if (pd.getMass(i) != b.mass)
      throw std::runtime_error("mesh check: vertex " + std::to_string(i) + "'s mass differs from the peer's");
  }
  const auto& tets = bar.getTetModels()[0]->getParticleMesh().getTets();
  if (tets.size() != 4 * b.tets.size()) throw std::runtime_error("mesh check: tet count differs");
  for (std::size_t t = 0; t < b.tets.size(); ++t)
    for (int k = 0; k < 4; ++k)
      if (tets[4 * t + k] != b.tets[t][k])
        throw std::runtime_error("mesh check: tet " + std::to_string(t) + " differs from the peer's bar");
  // The demo's pins: every vertex i·height·depth + j·depth + k with i = 0.
  std::vector<unsigned> pins;
  for (int j = 0; j < b.height; ++j)
    for (int k = 0; k < b.depth; ++k) pins.push_back(unsigned(j * b.depth + k));
  if (pins != b.pinned) throw std::runtime_error("mesh check: the pinned vertices are not the demo's i = 0 end");
}

}  // namespace

int main(int argc, char** argv) {
  const peer_bench::BarOptions o = peer_bench::parse_bar(
      argc, argv,
      "  --method: fem (default: the peer's FEM based XPBD, solid method 3; --young, --poisson) or shape-matching\n"
      "  (solid method 5; --stiffness); --threads: omp_set_num_threads; --solver and --double are ignored (the peer\n"
      "  has one solver; its Real is double); --damping: the driver scales the velocities by 1 − damping·dt after\n"
      "  each step (the peer has no damping of its own)\n");
  const std::string method = o.method.empty() ? "fem" : o.method;
  if (method != "fem" && method != "shape-matching") {
    std::fprintf(stderr, "peer_bar: --method: fem or shape-matching, got '%s'\n", o.method.c_str());
    return 2;
  }
  const unsigned solid_method = method == "fem" ? 3u : 5u;
  try {
    const peer_bench::Bar b = peer_bench::read_bar(o.mesh);
    if (o.threads > 0) omp_set_num_threads(o.threads);
    check_against_peer_bar(b);

    const Clock::time_point t0 = Clock::now();
    SimulationModel* model = peer_bench::start_peer_simulation(o.dt, o.substeps, o.iterations);  // as the demo
    const Vector3r gravity(Simulation::getCurrent()->getVecValue<Real>(Simulation::GRAVITATION));
    if (gravity != Vector3r(0, -9.81, 0)) throw std::runtime_error("the peer's gravity is not (0, -9.81, 0)");

    // The mesh from the file, through the call addRegularTetModel ends in; then its masses and the demo's pins.
    std::vector<Vector3r> points(b.x.size());
    for (std::size_t i = 0; i < b.x.size(); ++i) points[i] = Vector3r(b.x[i][0], b.x[i][1], b.x[i][2]);
    std::vector<unsigned int> indices;
    for (const auto& t : b.tets) indices.insert(indices.end(), t.begin(), t.end());
    model->addTetModel(unsigned(points.size()), unsigned(b.tets.size()), points.data(), indices.data());
    ParticleData& pd = model->getParticles();
    for (unsigned i = 0; i < pd.size(); ++i) pd.setMass(i, static_cast<Real>(b.mass));
    for (unsigned i : b.pinned) pd.setMass(i, 0.0);

    // The demo's createMesh: the solid method's constraints, with its stiffness (Young's modulus for the FEM XPBD
    // method, the shape matching's k), its Poisson ratio and its defaults for the rest.
    TetModel* tm = model->getTetModels()[0];
    model->setSolidSimulationMethod(int(solid_method));  // no callback set: only the value
    model->setSolidStiffness(static_cast<Real>(solid_method == 3 ? o.young : o.stiffness));
    model->setSolidPoissonRatio(static_cast<Real>(o.poisson));
    model->addSolidConstraints(tm, solid_method, model->getSolidStiffness(), model->getSolidPoissonRatio(),
                               model->getSolidVolumeStiffness(), model->getSolidNormalizeStretch(),
                               model->getSolidNormalizeShear());

    // The constraints the peer made must be one per tet of the file, on its corners in its order.
    const int type = solid_method == 3 ? XPBD_FEMTetConstraint::TYPE_ID : ShapeMatchingConstraint::TYPE_ID;
    std::size_t nc = 0;
    for (Constraint* k : model->getConstraints()) {
      if (k->getTypeId() != type) throw std::runtime_error("unexpected constraint type in the peer's model");
      if (nc >= b.tets.size() || k->numberOfBodies() != 4)
        throw std::runtime_error("the peer made more constraints than the file has tets");
      for (int j = 0; j < 4; ++j)
        if (k->m_bodies[j] != b.tets[nc][j])
          throw std::runtime_error("constraint " + std::to_string(nc) + " differs from the file's tet");
      ++nc;
    }
    if (nc != b.tets.size())
      throw std::runtime_error("the peer made " + std::to_string(nc) + " constraints for " +
                               std::to_string(b.tets.size()) + " tets (a degenerate tet?)");

    peer_bench::BarResult r;
    r.engine = "peer";
    r.precision = sizeof(Real) == 8 ? "double" : "float";
    r.method = method;
    r.solver = "peer-colored-gs";
    r.particles = pd.size();
    r.tets = tm->getParticleMesh().numTets();
    r.constraints = nc;
    model->initConstraintGroups();  // the peer's greedy coloring (its first step would do it): set-up
    r.colors = (long long)model->getConstraintGroups().size();
    r.threads = omp_get_max_threads();
    r.setup_ms = peer_bench::ms_since(t0);

    TimeStep* step = Simulation::getCurrent()->getTimeStep();
    const Real keep = static_cast<Real>(std::max(0.0, 1.0 - o.damping * o.dt));
    const auto tip = [&] {
      return peer_bench::tip_of(b, [&](unsigned i) {
        const Vector3r& p = pd.getPosition(i);
        return peer_bench::Point{double(p[0]), double(p[1]), double(p[2])};
      });
    };
    char made_by[160];
    std::snprintf(made_by, sizeof made_by, "peer %s, %s, %d x %d, E = %g Pa, nu = %g, k = %g, damping %g",
                  r.precision.c_str(), method.c_str(), o.substeps, o.iterations, o.young, o.poisson, o.stiffness,
                  o.damping);
    peer_bench::run_bar(
        o, b, r,
        [&] {
          step->step(*model);
          if (o.damping > 0)
            for (unsigned i = 0; i < pd.size(); ++i) pd.getVelocity(i) *= keep;
        },
        tip, made_by);
    peer_bench::print_bar(o, b, r);
    delete Simulation::getCurrent();
    delete model;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_bar: %s\n", e.what());
    return 1;
  }
  return 0;
}
