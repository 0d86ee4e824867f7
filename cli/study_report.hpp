#pragma once
// The results of `pbd study`: the table on stdout, the dominance check, the JSON report.
#include "study_options.hpp"
#include "study_record.hpp"

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <vector>

namespace pbd::cli {

/// Does the colored solver at `threads` dominate the serial solver on one scene? For every serial point
/// (iterations) it looks for a colored point that is faster (median ms per step) with no higher error.
struct Dominance {
  std::string scene;                   ///< scene
  int substeps = 1;                    ///< substeps
  std::string solver;                  ///< the parallel solver compared with serial: "colored" or "block"
  int threads = 0;                     ///< threads of its points
  std::string error;                   ///< the error compared: "ref_error" or "rms_violation"
  int serial_points = 0;               ///< serial points on this scene
  std::vector<int> undominated;        ///< iterations of the serial points none of its points dominates
};

/// One Dominance per (scene, substeps, parallel Gauss-Seidel solver: colored, block; error measure) with both serial
/// and that solver's records, comparing against its records at the most threads measured.
std::vector<Dominance> dominance(const std::vector<Record>& records);

/// Prints the table (one line per record, grouped by scene) and the dominance summary.
void print_table(std::ostream& out, const std::vector<Record>& records, const std::vector<Dominance>& dom);

/// The JSON report: {"study": {command, machine, options}, "references": [...], "records": [...], "dominance": [...]}.
nlohmann::json report_json(const StudyPlan& plan, const nlohmann::json& environment,
                           const std::vector<Reference>& references, const std::vector<Record>& records,
                           const std::vector<Dominance>& dom);

}  // namespace pbd::cli
