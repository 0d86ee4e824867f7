// load_tet_mesh: the tet mesh reader an extension names.
#include "pbd/io/tet_mesh_reader.hpp"

#include "pbd/detail/message.hpp"
#include "pbd/error.hpp"

#include <string>

namespace pbd {

TetMesh load_tet_mesh(const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".msh") return load_gmsh(file);
  if (ext == ".node" || ext == ".ele") return load_tetgen(file);
  throw Error(detail::message(file.string(), ": not a tet mesh file this library reads (extension \"", ext,
                              "\"); it reads .msh (Gmsh) and .node or .ele (TetGen)"));
}

}  // namespace pbd
