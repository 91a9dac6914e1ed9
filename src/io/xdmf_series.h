#pragma once
// `nsf export --format xdmf`: a run's frames as an XDMF 3 time series that reads without
// hyperslabs, so that meshio's xdmf.TimeSeriesReader and the Xdmf3 library (ParaView's XDMF3
// readers) read it as well as the Xdmf2 readers do. Two files:
//   <stem>.h5    every array of every frame as its own dataset: /frames/<k>/x, v, speed,
//                von_mises, tau, F (k the run's frame number), and /material, /object and
//                /connectivity (0..P-1, P×1) once
//   <stem>.xdmf  a temporal collection with one Uniform grid per frame: Polyvertex topology,
//                the frame's positions as geometry, and the arrays of io/frame_fields.h plus the
//                positions (`x`) as point attributes, since meshio's time series takes the
//                geometry from the first grid only.
// Layout: docs/VISUALISE.md. The HDF5 file is written under "<stem>.h5.tmp" (created exclusively)
// and renamed by finish(), then the XDMF file is written atomically; a writer destroyed without
// finish() deletes its temp file.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/run_reader.h"

namespace nsf {

class XdmfSeriesWriter {
 public:
  XdmfSeriesWriter(std::string xdmf_path, std::string h5_path, std::vector<uint16_t> material,
                   std::vector<uint16_t> object);
  ~XdmfSeriesWriter();
  XdmfSeriesWriter(const XdmfSeriesWriter&) = delete;
  XdmfSeriesWriter& operator=(const XdmfSeriesWriter&) = delete;

  // Frame `run_frame` of the run (its number in the run file names its group).
  void add_frame(size_t run_frame, const RunFrame& f);
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nsf
