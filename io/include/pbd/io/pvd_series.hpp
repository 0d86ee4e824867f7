#pragma once
/// \file pvd_series.hpp
/// ParaView data files (.pvd): a VTK Collection listing the frames of a series with their times, which ParaView
/// opens as one time-dependent dataset.
#include <filesystem>
#include <string>
#include <vector>

namespace pbd {

/// One frame of a series.
struct PvdFrame {
  double time = 0.0;  ///< simulated time of the frame, s (the DataSet's timestep)
  std::string file;   ///< the frame's file, relative to the .pvd's folder
};

/// The text of a .pvd file: <VTKFile type="Collection"> with one <DataSet timestep="t" part="0" file="..."/> per
/// frame, in the order given; times are written with %.17g (exact for a double), file names XML-escaped.
std::string pvd_text(const std::vector<PvdFrame>& frames);

/// Writes pvd_text to `file` through write_file_atomically (rewritten whole each time: an interrupted run leaves the
/// last complete list). Throws pbd::Error naming the file.
void write_pvd(const std::filesystem::path& file, const std::vector<PvdFrame>& frames);

}  // namespace pbd
