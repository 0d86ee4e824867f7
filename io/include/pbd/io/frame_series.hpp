#pragma once
/// \file frame_series.hpp
/// A series of frames of one simulation in one folder, as `pbd run --frames DIR --format obj|vtu` writes them:
/// DIR/<stem>_<step, 5 digits or more>.obj or .vtu, and for vtu DIR/<stem>.pvd listing every frame written so far.
#include "pbd/io/frame_topology.hpp"
#include "pbd/io/pvd_series.hpp"
#include "pbd/io/vtu_frame.hpp"
#include "pbd/world.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pbd {

/// The file format of a frame series.
enum class FrameFormat {
  obj,  ///< Wavefront OBJ, one object per body (frame_writer.hpp): Blender
  vtu,  ///< VTK XML UnstructuredGrid, one piece per body, with a .pvd (vtu_frame.hpp): ParaView
};

/// "obj" or "vtu".
const char* name(FrameFormat format);

/// The format named `text` ("obj" or "vtu"); throws pbd::Error naming it and the valid ones otherwise.
FrameFormat parse_frame_format(const std::string& text);

/// Throws pbd::Error naming `stem` unless it is a plain file name: not empty, not "." or "..", and without '/', '\\'
/// or a control byte (below 0x20, or 0x7f), so that no frame lands outside its folder.
void check_frame_stem(const std::string& stem);

/// Writes the frames of one world, one call per frame; every file goes through write_file_atomically.
class FrameSeries {
 public:
  /// A series in folder `dir` (which must exist) named `stem` (check_frame_stem), drawing `topology`. Throws
  /// pbd::Error for a bad stem.
  FrameSeries(std::filesystem::path dir, std::string stem, FrameFormat format, FrameTopology topology);

  /// Writes the frame of `world` at `step` (≥ 0) to frame_file(step); for vtu then rewrites the .pvd with every frame
  /// written so far (a step written again replaces its entry), timestep = world.time() in s. Throws pbd::Error naming
  /// the file that could not be written, or the body that does not fit the world; a failed frame is not listed.
  template <class Real> void write(const World<Real>& world, long step);

  /// DIR/<stem>_<step as %05ld>.obj or .vtu.
  std::filesystem::path frame_file(long step) const;
  /// DIR/<stem>.pvd (written for vtu only).
  std::filesystem::path pvd_file() const;
  /// Number of frames written so far.
  std::size_t frames_written() const { return written_; }
  /// The format of the series.
  FrameFormat format() const { return format_; }

 private:
  std::filesystem::path dir_;
  std::string stem_;
  FrameFormat format_;
  FrameTopology topology_;
  std::optional<VtuCellConstraints> cells_;  // found at the first vtu frame, again if the world's constraints change
  std::vector<PvdFrame> pvd_;
  std::size_t written_ = 0;
};

}  // namespace pbd
