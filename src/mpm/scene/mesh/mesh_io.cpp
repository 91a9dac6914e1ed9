#include "mpm/scene/mesh/mesh_io.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>

#include "core/error.h"

namespace nsf {

TriangleMesh read_triangle_mesh(const std::string& file, const std::string& key_path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    fail("scene: '", key_path, "' = \"", file, "\": mesh file not found");

  Assimp::Importer importer;
  // Triangulate turns OBJ polygons into triangles; PreTransformVertices bakes node transforms
  // (formats with a scene graph) into the vertices, so the mesh is what a viewer would show.
  // No step that merges by normal or drops "degenerate" faces: welding is done by position below.
  const aiScene* scene =
      importer.ReadFile(file, aiProcess_Triangulate | aiProcess_PreTransformVertices);
  if (!scene)
    fail("scene: '", key_path, "' = \"", file,
         "\": cannot read the mesh file: ", importer.GetErrorString());

  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    const int base = static_cast<int>(mesh.vertices.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      mesh.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines bound no volume
      mesh.triangles.push_back({base + int(face.mIndices[0]), base + int(face.mIndices[1]),
                                base + int(face.mIndices[2])});
    }
  }
  weld_vertices(mesh);
  if (mesh.triangles.empty())
    fail("scene: '", key_path, "' = \"", file,
         "\": the mesh file holds no (non-degenerate) triangle");
  return mesh;
}

}  // namespace nsf
