#pragma once
/// \file frame_series.hpp
/// A series of frames of one simulation in one folder, as `pbd run --frames DIR --format obj|vtu` writes them:
/// DIR/<stem>_<step, 5 digits or more>.obj or .vtu, and for vtu DIR/<stem>.pvd listing every frame written so far.
#include "pbd/io/frame_topology.hpp"
#include "pbd/io/pvd_series.hpp"
#include "pbd/io/vtu_frame.hpp"
#include "pbd/world.hpp"

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pbd {

/// The file format of a frame series.
enum class FrameFormat {
  obj,  ///< Wavefront OBJ, one object per body (frame_writer.hpp): Blender
  vtu,  ///< VTK XML UnstructuredGrid, one piece with a body id per point and cell, and a .pvd (vtu_frame.hpp)
};

/// "obj" or "vtu".
const char* name(FrameFormat format);

/// The format named `text` ("obj" or "vtu"); throws pbd::Error naming it and the valid ones otherwise.
FrameFormat parse_frame_format(const std::string& text);

/// Throws pbd::Error naming `stem` unless it is a plain file name: not empty, not "." or "..", and without '/', '\\'
/// or a control byte (below 0x20, or 0x7f), so that no frame lands outside its folder.
void check_frame_stem(const std::string& stem);

/// Writes the frames of one world, one call per frame; every file goes through write_file_atomically, and a frame
/// file or .pvd name that something other than a regular file has taken (a FIFO, a device, a folder) is refused
/// without being opened.
class FrameSeries {
 public:
  /// A series in folder `dir` (which must exist) named `stem` (check_frame_stem), drawing `topology`. Throws
  /// pbd::Error for a bad stem.
  FrameSeries(std::filesystem::path dir, std::string stem, FrameFormat format, FrameTopology topology);
  /// The same with the time step `dt` (s, > 0 and finite) as the scene gives it, in double: frame times are
  /// step × dt. A World<float> steps by dt rounded to float, so step × its own dt is off by up to 6e-8 relative (1/60
  /// s: 90 steps give 1.5000000782 s); the scene's dt gives 1.5. Throws pbd::Error for a bad stem or dt.
  FrameSeries(std::filesystem::path dir, std::string stem, FrameFormat format, FrameTopology topology, double dt);

  /// Writes the frame of `world` at `step` (≥ 0) to frame_file(step); for vtu the frame joins the .pvd's list (a step
  /// written again replaces its entry). Its time (the .pvd's timestep and the frame's TimeValue, s) is step × dt in
  /// double, dt as given to the constructor, else the world's params().dt: a count of steps, not their sum, which
  /// drifts (so a world stepped other than by `step` steps of dt is not timed by this). The .pvd is rewritten after
  /// each of the first kPvdEveryFrame frames, then at most once per second (so a long run's rewrites add up to a
  /// bounded multiple of its size, and a stopped run's .pvd lags by at most a second), and by finish(). Throws
  /// pbd::Error naming the file that could not be written, the body that does not fit the world, or the first
  /// particle whose position or velocity is not finite (nothing is written then); a failed frame is not listed.
  template <class Real> void write(const World<Real>& world, long step);
  /// Before the first frame: removes the temporaries of this stem that a killed run left in the folder
  /// (remove_stale_temporaries), and writes and removes a probe file "<stem>.probe.<pid>.0.tmp" there. Throws pbd::Error naming
  /// the probe and the system's reason if the folder cannot hold a file (missing, read-only, full).
  void prepare() const;
  /// Draws `topology` from the next frame on (after fibers broke: frame_topology made anew draws the ones left).
  void set_topology(FrameTopology topology) {
    topology_ = std::move(topology);
    cells_.reset();
  }
  /// Writes the .pvd if frames were listed since it was last written (call once the run is over).
  void finish();
  /// Frames after each of which the .pvd is always rewritten.
  static constexpr std::size_t kPvdEveryFrame = 16;

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
  std::optional<double> dt_;                 // the scene's time step, if given
  std::optional<VtuCellConstraints> cells_;  // found at the first vtu frame, again if the world's constraints change
  std::map<long, PvdFrame> pvd_;  // by step
  bool pvd_pending_ = false;      // frames listed since the .pvd was last written
  std::chrono::steady_clock::time_point pvd_written_at_{};
  std::size_t written_ = 0;
};

}  // namespace pbd
