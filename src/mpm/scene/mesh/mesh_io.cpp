#include "mpm/scene/mesh/mesh_io.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <dlfcn.h>

#include <filesystem>
#include <memory>
#include <mutex>

#include "core/error.h"

namespace nsf {

namespace {

// Assimp's C API, loaded when a scene first names a mesh file: nothing of nsf links it, so the
// runtime a host ships (libnsf_runtime.so) needs it only for scenes with mesh shapes.
struct AssimpApi {
  decltype(&aiImportFile) import_file = nullptr;
  decltype(&aiReleaseImport) release = nullptr;
  decltype(&aiGetErrorString) error = nullptr;
};

const AssimpApi& assimp() {
  static AssimpApi api;
  static std::once_flag once;
  std::call_once(once, [] {
    void* lib = nullptr;
    for (const char* name : {"libassimp.so.5", "libassimp.so"})
      if ((lib = dlopen(name, RTLD_NOW | RTLD_LOCAL))) break;
    if (!lib) return;
    api.import_file = reinterpret_cast<decltype(&aiImportFile)>(dlsym(lib, "aiImportFile"));
    api.release = reinterpret_cast<decltype(&aiReleaseImport)>(dlsym(lib, "aiReleaseImport"));
    api.error = reinterpret_cast<decltype(&aiGetErrorString)>(dlsym(lib, "aiGetErrorString"));
  });
  return api;
}

// Assimp's error string is the library's one global: one import at a time.
std::mutex& import_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace

TriangleMesh read_triangle_mesh(const std::string& file, const std::string& key_path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    fail("scene: '", key_path, "' = \"", file, "\": mesh file not found");

  const AssimpApi& api = assimp();
  if (!api.import_file || !api.release || !api.error)
    fail("scene: '", key_path, "' = \"", file,
         "\": reading a mesh file needs the Assimp library (libassimp.so.5; on Debian: apt "
         "install libassimp5), which this process cannot load");
  std::lock_guard<std::mutex> lock(import_mutex());
  // Triangulate turns OBJ polygons into triangles; PreTransformVertices bakes node transforms
  // (formats with a scene graph) into the vertices, so the mesh is what a viewer would show.
  // No step that merges by normal or drops "degenerate" faces: welding is done by position below.
  const std::unique_ptr<const aiScene, decltype(api.release)> scene(
      api.import_file(file.c_str(), aiProcess_Triangulate | aiProcess_PreTransformVertices),
      api.release);
  if (!scene)
    fail("scene: '", key_path, "' = \"", file, "\": cannot read the mesh file: ", api.error());

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
