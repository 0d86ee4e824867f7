#pragma once
/// \file vtu_frame.hpp
/// Frames as VTK XML UnstructuredGrid files (.vtu) for ParaView: one <Piece> holding every particle of the world, in
/// world order (point i is particle i), and the cells of every body, body after body, with a `body` id per point and
/// per cell. One piece rather than one per body: readers disagree on several pieces (meshio 7.0 keeps only the last
/// piece's cells), while every reader reads one piece whole; the body id keeps what the pieces told apart (ParaView:
/// Threshold on body), and the header comment names each id's body. Every data array is inline base64 binary
/// (format="binary", header_type="UInt64", uncompressed, the machine's byte order): values round-trip bit for bit,
/// NaN included, at 4/3 of their size.
///
/// Per point: the position (Float32 for World<float>, Float64 for World<double>, m), and
///   body          Int32: the index of its body in FrameTopology::bodies
///   velocity      3 components, m/s
///   inverse_mass  1/kg (0 for a pinned particle)
///   pinned        UInt8: 1 where the inverse mass is 0, else 0
/// Cells of a body, in this order: its triangles (VTK_TRIANGLE, 5), its lines (VTK_LINE, 3), its tets (VTK_TETRA, 10,
/// corners p0..p3 of their constraint: positively oriented, as VTK wants), and, for a body with none of these, one
/// VTK_VERTEX (1) per particle so that ParaView draws it. Per cell: `body` (Int32, as per point), and each of these
/// only when the world has what it measures, so that no array is all NaN for want of constraints (Float64,
/// dimensionless, NaN on a cell without such a constraint; stretch and area are pbd::violation of metrics.hpp at the
/// frame's positions):
///   stretch       stretch constraints or fibers: on a line the relative stretch |(|x_a − x_b| − d)| / d of the
///                 stretch constraint it draws (a fiber line: its fiber's elastic strain); on a triangle the largest
///                 relative stretch of the stretch constraints joining two of its corners
///   area          area constraints: on a triangle the largest relative area error |A − A0| / A0 of the area
///                 constraints on its three corners
///   volume_ratio  tets: on a tet V / V0, its signed volume over its rest volume (< 0 once it is turned inside out);
///                 on a triangle that is a face of one of its body's tets, that tet's (so the surface ParaView draws
///                 over the tets shows the same colours)
///   strain        tets with a Neo-Hookean constraint: on such a tet the Green strain |½(FᵀF − I)| (Frobenius) of
///                 F = Ds·Dm⁻¹, as that constraint's violation; on a triangle on a tet's face, that tet's
///   fiber_strain, fiber_force            fibers drawn as lines: total strain, tension in N
///   tet_fiber_strain, tet_fiber_stress   tet fibers: on their tet, total strain, stress in Pa
/// The grid's FieldData holds TimeValue (Float64, 1 tuple): the frame's simulated time in s.
#include "pbd/io/frame_topology.hpp"
#include "pbd/world.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pbd {

/// Which constraints each triangle of a topology measures, and which tet it lies on, found once: triangles are
/// numbered over all bodies in order (body 0's first, then body 1's, ...).
struct VtuCellConstraints {
  static constexpr std::size_t kNoTet = std::size_t(-1);  ///< triangle_tet of a triangle on no tet's face
  std::vector<std::size_t> stretch_begin;  ///< triangle k's stretch constraints: stretch[stretch_begin[k], stretch_begin[k + 1])
  std::vector<Index> stretch;              ///< indices into world.constraints<StretchConstraint<Real>>()
  std::vector<std::size_t> area_begin;     ///< triangle k's area constraints: area[area_begin[k], area_begin[k + 1])
  std::vector<Index> area;                 ///< indices into world.constraints<AreaConstraint<Real>>()
  std::size_t num_stretch = 0;             ///< the world's number of stretch constraints when found
  std::size_t num_area = 0;                ///< the world's number of area constraints when found
  /// Per triangle, the first of its body's tets (an index into FrameBody::tets) with the triangle as a face, or kNoTet.
  std::vector<std::size_t> triangle_tet;
};

/// Finds the stretch constraints along each triangle's edges, the area constraints on its corners and the tet of its
/// body it is a face of.
template <class Real> VtuCellConstraints vtu_cell_constraints(const World<Real>& world, const FrameTopology& topology);

/// The text of a .vtu frame of `world` at world.time(). Throws pbd::Error naming `what` if the topology does not fit
/// the world, if `cells` was found for other constraints (the world's constraint counts differ), or naming the first
/// particle whose position or velocity is not finite (check_finite_state).
template <class Real>
std::string vtu_frame(const World<Real>& world, const FrameTopology& topology, const VtuCellConstraints& cells,
                      const std::string& what);

/// vtu_frame with `time` (s) as its TimeValue rather than world.time(): a series writes step × dt
/// (frame_series.hpp), which a time summed step by step drifts from.
template <class Real>
std::string vtu_frame_at_time(const World<Real>& world, const FrameTopology& topology, const VtuCellConstraints& cells,
                              double time, const std::string& what);

/// Writes vtu_frame to `file` through write_file_atomically: a failure leaves no half-written frame and no temporary.
/// Throws pbd::Error naming the file.
template <class Real>
void write_vtu_frame(const std::filesystem::path& file, const World<Real>& world, const FrameTopology& topology);

}  // namespace pbd
