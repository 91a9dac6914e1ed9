#pragma once
// One run frame as a binary little-endian PLY point cloud, the format Blender, Houdini,
// MeshLab and CloudCompare all import. Each vertex carries the scalar arrays of io/frame_fields.h,
// a vector as one property per component (v -> v_x v_y v_z):
//   x y z                 position (float32, or double with double_positions)
//   v_x v_y v_z speed     velocity and |v| (float32)
//   von_mises             von Mises stress of tau (float32, Pa)
//   material object       indices into the scene (uint16)
// Houdini turns every property into a point attribute; Blender's importer keeps the extra ones
// as attributes when asked (import_attributes, Blender 4.2 and later); meshio reads them all;
// VTK's vtkPLYReader (and so ParaView) reads the positions only (docs/VISUALISE.md).
#include <cstdint>
#include <string>
#include <vector>

#include "io/run_reader.h"

namespace nsf {

struct PlyOptions {
  bool double_positions = false;  // float is what most importers expect
  std::string comment;            // header comment, e.g. "scene sand_column frame 3 time 0.1"
};

// Written atomically (temp name + rename).
void write_ply(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
               const std::vector<uint16_t>& object, const PlyOptions& options = {});

}  // namespace nsf
