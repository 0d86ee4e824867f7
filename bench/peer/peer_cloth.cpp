// The peer (Bender et al., PositionBasedDynamics, MIT) on its own ClothDemo cloth, without the GUI: the same set-up
// as Demos/ClothDemo/main.cpp, with the cloth method "distance constraints" (1) and the bending method "dihedral"
// (1) instead of the demo's defaults (FEM triangles, isometric bending), the mesh read from make_cloth.py's file,
// stepped by the peer's own TimeStepController as the demo steps it, and one line of JSON as pbd_cloth prints.
// Built only with PBD_PEER_DIR (bench/peer/CMakeLists.txt), against the peer's sources compiled directly.
#include "cloth_common.hpp"
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

#include <cmath>
#include <cstdio>
#include <exception>

// The static members the peer's demos define in DemoBase.cpp.
INIT_LOGGING
INIT_TIMING

using namespace PBD;
using peer_bench::Clock;

namespace {

// The peer's own ClothDemo grid, for checking that make_cloth.py wrote the same mesh (positions bit for bit).
void check_against_peer_grid(const peer_bench::Cloth& c) {
  SimulationModel grid;
  grid.init();
  grid.addRegularTriangleModel(c.n, c.n, Vector3r(0, 1, 0), AngleAxisr(M_PI * 0.5, Vector3r(1, 0, 0)).matrix(),
                               Vector2r(c.width, c.height));
  const ParticleData& pd = grid.getParticles();
  if (pd.size() != c.x.size()) throw std::runtime_error("mesh check: vertex count differs from the peer's grid");
  for (unsigned i = 0; i < pd.size(); ++i)
    for (int d = 0; d < 3; ++d)
      if (pd.getPosition(i)[d] != c.x[i][d])
        throw std::runtime_error("mesh check: vertex " + std::to_string(i) + " differs from the peer's grid");
  const auto& faces = grid.getTriangleModels()[0]->getParticleMesh().getFaces();
  if (faces.size() != 3 * c.tris.size()) throw std::runtime_error("mesh check: triangle count differs");
  for (std::size_t t = 0; t < c.tris.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (faces[3 * t + k] != c.tris[t][k])
        throw std::runtime_error("mesh check: triangle " + std::to_string(t) + " differs from the peer's grid");
}

}  // namespace

int main(int argc, char** argv) {
  const peer_bench::Options o =
      peer_bench::parse(argc, argv, "  --threads: omp_set_num_threads; --solver, --double, --tethers and --hierarchy "
                                    "are ignored (the peer has one solver; its Real is double)\n");
  try {
    const peer_bench::Cloth c = peer_bench::read_cloth(o.mesh);
    if (o.threads > 0) omp_set_num_threads(o.threads);
    check_against_peer_grid(c);

    const Clock::time_point t0 = Clock::now();
    SimulationModel* model = peer_bench::start_peer_simulation(o.dt, o.substeps, o.iterations);  // as the demo

    // The mesh from the file, through the same call addRegularTriangleModel ends in (so the peer builds the edges).
    std::vector<Vector3r> points(c.x.size());
    for (std::size_t i = 0; i < c.x.size(); ++i) points[i] = Vector3r(c.x[i][0], c.x[i][1], c.x[i][2]);
    std::vector<unsigned int> indices;
    for (const auto& t : c.tris) indices.insert(indices.end(), t.begin(), t.end());
    TriangleModel::ParticleMesh::UVIndices uv_indices(indices.begin(), indices.end());
    TriangleModel::ParticleMesh::UVs uvs(c.x.size());
    for (std::size_t i = 0; i < c.x.size(); ++i) uvs[i] = Vector2r(c.x[i][0] / c.width, c.x[i][2] / c.height);
    model->addTriangleModel(unsigned(points.size()), unsigned(c.tris.size()), points.data(), indices.data(),
                            uv_indices, uvs);
    ParticleData& pd = model->getParticles();
    for (unsigned i = 0; i < pd.size(); ++i) pd.setMass(i, static_cast<Real>(c.mass));
    for (unsigned i : c.pinned) pd.setMass(i, 0.0);

    // The demo's createMesh with cloth method 1 (DistanceConstraint per edge, k = 1) and bending method 1
    // (DihedralConstraint per interior edge, k = 0.01).
    TriangleModel* tm = model->getTriangleModels()[0];
    model->setClothSimulationMethod(1);
    model->setClothBendingMethod(1);
    model->setClothStiffness(static_cast<Real>(o.k_distance));
    model->addClothConstraints(tm, 1, model->getClothStiffness(), model->getClothStiffnessXX(),
                               model->getClothStiffnessYY(), model->getClothStiffnessXY(),
                               model->getClothPoissonRatioXY(), model->getClothPoissonRatioYX(),
                               model->getClothNormalizeStretch(), model->getClothNormalizeShear());
    model->setClothBendingStiffness(static_cast<Real>(o.k_bending));
    model->addBendingConstraints(tm, 1, model->getClothBendingStiffness());

    // The constraints the peer made must be the file's, in the file's order (pbd_cloth adds the file's).
    std::size_t nd = 0, nb = 0;
    for (Constraint* k : model->getConstraints()) {
      if (k->getTypeId() == DistanceConstraint::TYPE_ID) {
        if (nd >= c.edges.size() || k->m_bodies[0] != c.edges[nd][0] || k->m_bodies[1] != c.edges[nd][1])
          throw std::runtime_error("distance constraint " + std::to_string(nd) + " differs from the file's edge");
        ++nd;
      } else if (k->getTypeId() == DihedralConstraint::TYPE_ID) {
        for (int j = 0; j < 4; ++j)
          if (nb >= c.quads.size() || k->m_bodies[j] != c.quads[nb][j])
            throw std::runtime_error("dihedral constraint " + std::to_string(nb) + " differs from the file's quad");
        ++nb;
      } else {
        throw std::runtime_error("unexpected constraint type in the peer's model");
      }
    }
    if (nd != c.edges.size() || nb != c.quads.size())
      throw std::runtime_error("the peer made " + std::to_string(nd) + " distance and " + std::to_string(nb) +
                               " dihedral constraints, the file has " + std::to_string(c.edges.size()) + " and " +
                               std::to_string(c.quads.size()));

    peer_bench::Result r;
    r.engine = "peer";
    r.precision = sizeof(Real) == 8 ? "double" : "float";
    r.solver = "peer-colored-gs";
    r.particles = pd.size();
    r.distance = nd;
    r.bending = nb;
    model->initConstraintGroups();  // the peer's greedy coloring (its first step would do it): set-up
    r.colors = (long long)model->getConstraintGroups().size();
    r.threads = omp_get_max_threads();
    r.setup_ms = peer_bench::ms_since(t0);

    TimeStep* step = Simulation::getCurrent()->getTimeStep();
    auto error = [&] {
      return peer_bench::stretch(c, [&](unsigned i) {
        const Vector3r& p = pd.getPosition(i);
        return std::array<double, 3>{double(p[0]), double(p[1]), double(p[2])};
      });
    };
    r.ms_per_step = peer_bench::timed_steps(o, r, [&](int) { step->step(*model); }, [&] { return error().rms; });
    r.error = error();
    peer_bench::print(o, c, r);
    delete Simulation::getCurrent();
    delete model;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_cloth: %s\n", e.what());
    return 1;
  }
  return 0;
}
