#pragma once
// One run frame for ParaView / VisIt / meshio, as a point cloud with one VTK_VERTEX cell per
// particle and the arrays of io/frame_fields.h as point data: v, speed, von_mises, tau, F,
// material, object. Two flavours: legacy ".vtk" UNSTRUCTURED_GRID (big-endian binary, as the legacy
// format prescribes; the arrays as field data, which every legacy reader reads whole) and XML
// ".vtu" UnstructuredGrid (raw appended little-endian data, the more compact and faster-loading
// one). Collection files list the frames with their times so ParaView loads the whole run as one
// time series. All files are written atomically.
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
