#pragma once
// One run frame for ParaView / VisIt, as a point cloud with per-point data:
//   velocity (3), speed, von_mises (Pa), tau (Kirchhoff stress, 3x3), F (elastic deformation
//   gradient, 3x3), material, object.
// Two flavours: legacy ".vtk" POLYDATA (one vertex cell per particle; big-endian binary, as the
// legacy format prescribes) and XML ".vtu" UnstructuredGrid (raw appended little-endian data,
// the more compact and faster-loading one). Collection files list the frames with their times so
// ParaView loads the whole run as one time series. All files are written atomically.
#include <cstdint>
#include <string>
#include <vector>

#include "io/run_reader.h"

namespace nsf {

struct VtkFrameInfo {
  std::string title;  // legacy header line / a comment
  double time = 0;    // stored as TIME (legacy) or TimeValue (XML) field data
};

void write_vtk_legacy(const std::string& path, const RunFrame& f,
                      const std::vector<uint16_t>& material, const std::vector<uint16_t>& object,
                      const VtkFrameInfo& info);

void write_vtu(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
               const std::vector<uint16_t>& object, const VtkFrameInfo& info);

struct SeriesEntry {
  std::string file;  // relative to the collection file
  double time = 0;
};

// ParaView Data collection (.pvd) of XML files.
void write_pvd(const std::string& path, const std::vector<SeriesEntry>& entries);
// ParaView's JSON file series (.vtk.series): the way to give legacy .vtk files their times.
void write_vtk_series(const std::string& path, const std::vector<SeriesEntry>& entries);

}  // namespace nsf
