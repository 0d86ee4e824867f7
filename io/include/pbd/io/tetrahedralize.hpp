#pragma once
/// \file tetrahedralize.hpp
/// A closed triangle surface filled with tets by TetGen (the `tetgen` program, which scripts/deps installs).
#include "pbd/io/mesh.hpp"
#include "pbd/io/tet_mesh.hpp"

#include <string>

namespace pbd {

/// How finely and how well shaped tetrahedralize fills a surface.
struct TetrahedralizeOptions {
  /// Largest circumradius / shortest edge of a tet (tetgen -q): smaller gives rounder tets and more of them. Finite
  /// and >= 1: below 1 tetgen does not finish (the pig at 0.9 ran for more than 30 s; at 1.0 it takes 0.06 s).
  double max_radius_edge_ratio = 1.5;
  /// Largest tet volume in m^3 (tetgen -a); 0 = no limit. Finite and >= 0, and not below the enclosed volume / 10^7
  /// (so at most about 10^7 tets). With keep_surface it holds away from the surface only: tetgen cannot split a tet
  /// that would need a vertex on it (the pig at 5e-5 keeps tets of up to 1.3e-4 there).
  double max_volume = 0.0;
  /// Keep the surface as it is (tetgen -Y): then the surface's vertices are the mesh's first ones (same index, same
  /// coordinates) and its triangles are exactly the mesh's boundary faces, and tetgen adds vertices inside only.
  /// false lets tetgen also split boundary triangles (vertices added on the surface; the surface's vertices are still
  /// the mesh's first ones): better-shaped tets next to a coarse surface, a boundary that no longer matches it.
  bool keep_surface = true;
};

/// Fills `surface` with positively oriented tets (tet_mesh.hpp) by running TetGen 1.5's `tetgen` program on it in a
/// private temporary directory, removed afterwards on every path. The mesh's first surface.num_vertices() vertices
/// are the surface's own, at exactly its coordinates, and its tets fill the enclosed volume (checked to 1e-9 of it).
/// Deterministic: the same surface and options give the same mesh. Refuses, with a pbd::Error starting with
/// `source`, before running tetgen: a surface that is not closed, manifold and consistently oriented ("source: cannot
/// fill with tets:" and the defect closed_mesh_defect names), a vertex on no triangle, a non-finite coordinate, an
/// inside-out or flat surface, and options out of range (naming the option). Afterwards: tetgen missing ("tetgen is
/// not installed; run scripts/deps"), tetgen failing or killed (its exit status or signal and its last output lines;
/// when the surface intersects itself, which TetGen cannot fill, tetgen -d's count of intersecting faces and the
/// first pair as triangle indices), and output that is missing or malformed, fails check_tet_mesh, does not fill the
/// enclosed volume or, with keep_surface, does not keep the surface.
/// Why the program: Debian bookworm ships TetGen as the `tetgen` program only (no libtet -dev package to link), and
/// Gmsh's library, the other mesher packaged there, pulls in a far larger dependency tree; a short-lived process
/// and two text files cost little next to the meshing (the pig: about 0.03 s in all).
TetMesh tetrahedralize(const TriangleMesh& surface, const TetrahedralizeOptions& options, const std::string& source);

}  // namespace pbd
