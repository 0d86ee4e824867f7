#pragma once
// What both peer drivers (peer_cloth.cpp, peer_bar.cpp) set up as the peer's demos do, before their own model: the
// current Simulation (its init makes the TimeStepController), a model, the time step and the controller's split.
// Built only with PBD_PEER_DIR, as the drivers.
#include "Simulation/Simulation.h"
#include "Simulation/SimulationModel.h"
#include "Simulation/TimeManager.h"
#include "Simulation/TimeStepController.h"

namespace peer_bench {

/// A new model, made the current Simulation's, with time step dt and `substeps` × `iterations` in the peer's
/// TimeStepController. The caller deletes Simulation::getCurrent() at the end, as the demos do.
inline PBD::SimulationModel* start_peer_simulation(double dt, int substeps, int iterations) {
  using namespace PBD;
  SimulationModel* model = new SimulationModel();
  model->init();
  Simulation::getCurrent()->setModel(model);
  TimeManager::getCurrent()->setTimeStepSize(static_cast<Real>(dt));
  auto* controller = static_cast<TimeStepController*>(Simulation::getCurrent()->getTimeStep());
  controller->setValue<unsigned int>(TimeStepController::NUM_SUB_STEPS, unsigned(substeps));
  controller->setValue<unsigned int>(TimeStepController::MAX_ITERATIONS, unsigned(iterations));
  return model;
}

}  // namespace peer_bench
