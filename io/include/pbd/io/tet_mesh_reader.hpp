#pragma once
/// \file tet_mesh_reader.hpp
/// Tetrahedral meshes from Gmsh (.msh) and TetGen (.node and .ele) files, read and checked in one call: a reader
/// returns a TetMesh that check_tet_mesh accepts, or throws a pbd::Error naming the file and where in it what is
/// wrong. Both readers keep only the nodes some tet names (a node no tet names would be a free particle), in their
/// order in the file, numbered from 0.
#include "pbd/io/tet_mesh.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace pbd {

/// Largest file the tet mesh readers read (each of TetGen's two).
inline constexpr std::uintmax_t kMaxTetMeshBytes = 512u << 20;

/// Loads the 4-node tetrahedra (element type 4) of a Gmsh MSH file, ASCII or binary (either byte order): versions
/// 2.2 (and 2.0, 2.1, which have the same layout), 4.1 and, in ASCII only as Gmsh writes it, 4.0. Reads the sections
/// up to the first $Elements: $MeshFormat (first), $Nodes (any number, before $Elements, as the format has them) and
/// $Elements; skips $Entities, $PhysicalNames and any other section before $Elements; reads nothing after it. Elements
/// of dimension 0 to 2 (points, lines, triangles, quadrangles: Gmsh writes the boundary's too) are skipped; every
/// other volume element (higher-order tets, hexahedra, prisms, pyramids) is refused, as dropping it would leave part
/// of the body out. Node tags may be sparse and in any order. An ASCII file is read a line per record, as Gmsh writes
/// it (a node, an element, a node tag or a node's coordinates); parametric coordinates after x, y, z (version 4) are
/// skipped. Throws pbd::Error naming the file and the line ("bar.msh:17: node tag 5 appears twice (first at line 9)")
/// or, past the first binary data, the section and byte offset: a missing, empty, non-regular (a directory, a FIFO:
/// checked before opening, so it never blocks) or oversize (kMaxTetMeshBytes) file; an unsupported version, file type
/// or data size; a wrong endianness check; a malformed, non-numeric or non-finite value; a count the section does not
/// hold (checked against the bytes left before anything is allocated), truncated binary data or a section without
/// its $End line; a node tag 0 or given twice; an element naming a node $Nodes does not have; an element type it
/// does not know or refuses (above); no tet at all; an inverted or degenerate tet (check_tet_mesh, which names it by
/// its index among the file's tets, from 0; the message then says which element and where).
TetMesh load_gmsh(const std::filesystem::path& file);

/// Parses the bytes of an MSH file as load_gmsh does (at most kMaxTetMeshBytes); `source` names it in messages.
TetMesh parse_gmsh(std::string_view bytes, const std::string& source);

/// Loads a TetGen mesh: `file` is x.node, x.ele or their stem x (x.1 for tetgen's x.1.node), and both x.node and
/// x.ele are read. '#' starts a comment; blank lines are skipped. x.node: a header "<points> [3 [<attributes>
/// [<boundary marker 0 or 1>]]]", then one line per point "<number> <x> <y> <z> [attributes] [marker]", numbered
/// consecutively from 0 or from 1 (the first point says which; the .ele file numbers nodes the same way). x.ele: a
/// header "<tets> [4 [<attributes>]]", then one line per tet "<number> <n0> <n1> <n2> <n3> [attributes]".
/// Attributes and markers are counted but not read. TetGen writes every tet positively oriented in TetGen's own
/// sense, which is this library's (see tetgen_reader.cpp), so corners are kept in their order. Throws pbd::Error
/// naming the file and the line ("x.ele:3: tet 2 names node 99, which x.node does not have ..."): a missing, empty,
/// non-regular or oversize file (either one); a header or line with a missing, extra, non-numeric or non-finite
/// value; a dimension other than 3; points not numbered consecutively from 0 or 1; an .ele of 10-node tets (tetgen
/// -o2) or any node count but 4; no points or no tets, or a count of them the file does not hold (checked against its
/// size before anything is allocated); a tet naming a node the .node
/// file does not have; an inverted or degenerate tet (check_tet_mesh names it by its index from 0, then the message
/// gives its number and line in the .ele file).
TetMesh load_tetgen(const std::filesystem::path& file);

/// Parses the texts of a TetGen .node and .ele file as load_tetgen does (each at most kMaxTetMeshBytes); the
/// sources name them in messages.
TetMesh parse_tetgen(std::string_view node_text, const std::string& node_source, std::string_view ele_text,
                     const std::string& ele_source);

/// Loads a tet mesh by the extension of `file`, in lower case as Gmsh and TetGen write it: .msh with load_gmsh, .node
/// or .ele with load_tetgen. Throws pbd::Error naming the file and the extensions accepted for any other extension,
/// or what the reader throws.
TetMesh load_tet_mesh(const std::filesystem::path& file);

}  // namespace pbd
