#pragma once
/// \file mesh_generators.hpp
/// Procedural triangle meshes: grid, dodecahedron, icosphere, tube. Closed ones wind counter-clockwise seen from
/// outside (positive volume), centred on the origin.
#include "pbd/io/mesh.hpp"

namespace pbd {

/// An N×N vertex grid in the plane z = 0 spanning [0, size]², each quad split along the same diagonal (the layout
/// of add_cloth: vertex (i, j) is j·N + i). Open; N ≥ 2.
TriangleMesh grid_mesh(int resolution, double size);

/// A regular dodecahedron with circumradius `radius`, each pentagon split into 5 triangles around a vertex at its
/// centre (20 + 12 vertices, 60 triangles), so the faces can bulge when it inflates. Closed.
TriangleMesh dodecahedron_mesh(double radius);

/// An icosahedron subdivided `level` times (0..8; each level splits every triangle into 4), projected onto the
/// sphere of `radius`: 10·4^level + 2 vertices. Closed.
TriangleMesh icosphere_mesh(int level, double radius);

/// A cylinder along z from −length/2 to length/2: `rings` ≥ 2 rings of `segments` ≥ 3 vertices, optionally closed
/// with a fan cap at each end (one centre vertex each).
TriangleMesh tube_mesh(int segments, int rings, double radius, double length, bool capped);

}  // namespace pbd
