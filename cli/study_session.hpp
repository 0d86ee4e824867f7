#pragma once
// One run of `pbd study`: what it measures, in what order, and the progress it prints.
//
// Main mode: for each scene, its converged reference first (serial, double, plan.reference), then one group per
// budget split (substeps × iterations): every solver × thread count of the split, timed in interleaved rounds, then
// the shared-nothing reference of each thread count above 1. Scaling mode: one group per scene at plan.split over
// the parallel solvers and every thread count, with the shared-nothing reference, and no converged reference.
// With --shard I/N only the groups g with g mod N = I − 1 run (with the references and shared-nothing runs of their
// scenes), so N shards together run every group once and `pbd study merge` joins them.
#include "study_options.hpp"
#include "study_report.hpp"

namespace pbd::cli {

/// Runs the plan's measurements (progress and the estimated time left on stderr) and returns the finished report.
Report run_study(const StudyPlan& plan);

/// Prints on stdout what the plan would run, per scene and variant: its groups, points and estimated time (the
/// reference's first budget and the half of it included; raising it is not), and the total.
void estimate_study(const StudyPlan& plan);

}  // namespace pbd::cli
