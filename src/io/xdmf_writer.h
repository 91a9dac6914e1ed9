#pragma once
// The XDMF sidecar of a run file: <run>.xdmf next to <run>.h5, an XML file that tells ParaView's
// and VisIt's Xdmf (2) readers how to read the HDF5 datasets as a time series of point clouds (one
// Polyvertex grid per frame, frame k of each dataset read by hyperslab, the per-particle fields as
// attributes under the names of io/frame_fields.h). Layout and the readers that read it:
// docs/OUTPUT.md. Readers without hyperslabs read io/xdmf_series.h's files instead.
#include <cstddef>
#include <string>
#include <vector>

namespace nsf {

// The XDMF text for a run file named `h5_name` (relative to the sidecar: its file name) holding
// `particles` particles and one frame per entry of `times`.
std::string run_xdmf(const std::string& h5_name, size_t particles,
                     const std::vector<double>& times);

// "<dir>/<stem>.xdmf" for a run file path.
std::string xdmf_path_for(const std::string& run_path);

}  // namespace nsf
