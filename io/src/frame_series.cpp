#include "pbd/io/frame_series.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/io/atomic_file.hpp"
#include "pbd/io/frame_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace pbd {
namespace {

using detail::message;

// `s` quoted for a message, control bytes shown as \xNN.
std::string shown(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      out += hex;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

const char* name(FrameFormat format) { return format == FrameFormat::vtu ? "vtu" : "obj"; }

FrameFormat parse_frame_format(const std::string& text) {
  if (text == "obj") return FrameFormat::obj;
  if (text == "vtu") return FrameFormat::vtu;
  throw Error(message("unknown frame format ", shown(text), " (expected obj or vtu)"));
}

void check_frame_stem(const std::string& stem) {
  const char* why = nullptr;
  if (stem.empty()) why = "it is empty";
  else if (stem == "." || stem == "..") why = "it names a folder";
  else if (stem.find_first_of("/\\") != std::string::npos) why = "it contains '/' or '\\'";
  else if (std::any_of(stem.begin(), stem.end(), [](char c) {
             const auto u = static_cast<unsigned char>(c);
             return u < 0x20 || u == 0x7f;
           }))
    why = "it contains a control character";
  if (why)
    throw Error(message("frame file stem ", shown(stem), " is not a plain file name (", why,
                        "): frames must stay in their folder"));
}

FrameSeries::FrameSeries(std::filesystem::path dir, std::string stem, FrameFormat format, FrameTopology topology)
    : dir_(std::move(dir)), stem_(std::move(stem)), format_(format), topology_(std::move(topology)) {
  check_frame_stem(stem_);
}

FrameSeries::FrameSeries(std::filesystem::path dir, std::string stem, FrameFormat format, FrameTopology topology,
                         double dt)
    : FrameSeries(std::move(dir), std::move(stem), format, std::move(topology)) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw Error(message("frame series ", shown(stem_), ": the time step must be positive and finite (", dt, ")"));
  dt_ = dt;
}

std::filesystem::path FrameSeries::frame_file(long step) const {
  char suffix[48];
  std::snprintf(suffix, sizeof suffix, "_%05ld.%s", step, name(format_));
  return dir_ / (stem_ + suffix);
}

void FrameSeries::prepare() const {
  remove_stale_temporaries(dir_, stem_);
  // A probe of the folder written as a frame is (write_file_atomically), removed at once: a folder on a read-only
  // or full file system is refused before the run, not after its first step. Named as a temporary of this process,
  // so that the next run removes it should this one be killed before it does.
  const std::filesystem::path probe = dir_ / message(stem_, ".probe.", ::getpid(), ".0.tmp");
  write_file_atomically(probe, "pbd\n", NonRegularFile::refuse);
  std::error_code ec;
  std::filesystem::remove(probe, ec);
}

std::filesystem::path FrameSeries::pvd_file() const { return dir_ / (stem_ + ".pvd"); }

template <class Real> void FrameSeries::write(const World<Real>& world, long step) {
  if (step < 0) throw Error(message(frame_file(step).string(), ": the step must not be negative (", step, ")"));
  const std::filesystem::path file = frame_file(step);
  // A frame's name is made up here, not given by the user: whatever else has taken it (a FIFO, a device) is
  // refused without being opened, where writing to it could block forever.
  if (format_ == FrameFormat::obj) {
    write_file_atomically(file, obj_frame(world, topology_, file.string()), NonRegularFile::refuse);
    ++written_;
    return;
  }
  // vtu_frame checks the topology against the world (once per frame); the cell lookup below only reads it.
  if (!cells_ || cells_->num_stretch != world.template constraints<StretchConstraint<Real>>().size() ||
      cells_->num_area != world.template constraints<AreaConstraint<Real>>().size())
    cells_ = vtu_cell_constraints(world, topology_);
  // step × dt: the time of `step` steps as a count, where world.time() is their sum (which drifts from it).
  const double time = double(step) * dt_.value_or(double(world.params().dt));
  write_file_atomically(file, vtu_frame_at_time(world, topology_, *cells_, time, file.string()),
                        NonRegularFile::refuse);
  ++written_;
  pvd_[step] = {time, file.filename().string()};
  pvd_pending_ = true;
  if (written_ <= kPvdEveryFrame || std::chrono::steady_clock::now() - pvd_written_at_ >= std::chrono::seconds(1))
    finish();
}

void FrameSeries::finish() {
  if (!pvd_pending_) return;
  std::vector<PvdFrame> frames;
  frames.reserve(pvd_.size());
  for (const auto& [step, frame] : pvd_) frames.push_back(frame);
  write_file_atomically(pvd_file(), pvd_text(frames), NonRegularFile::refuse);
  pvd_pending_ = false;
  pvd_written_at_ = std::chrono::steady_clock::now();
}

template void FrameSeries::write(const World<float>&, long);
template void FrameSeries::write(const World<double>&, long);

}  // namespace pbd
