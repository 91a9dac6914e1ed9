#include "io/xdmf_writer.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "io/frame_fields.h"
#include "io/xml_escape.h"

namespace nsf {

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

struct Field {
  const char* name;  // attribute name: io/frame_fields.h, as in the export formats
  const char* dataset;
  size_t width;      // components per particle
  const char* type;  // XDMF AttributeType
  bool per_frame;
  const char* number;  // NumberType and Precision
};

const char* const kF64 = "NumberType=\"Float\" Precision=\"8\"";
const char* const kU16 = "NumberType=\"UInt\" Precision=\"2\"";

// tau is stored xx yy zz xy yz xz, not in XDMF's Tensor6 order (xx xy xz yy yz zz), so it is a
// plain 6-component "Matrix" attribute (the order VTK and ParaView use for a symmetric tensor).
const Field kFields[] = {
    {field_name::kVelocity, "/frames/v", 3, "Vector", true, kF64},
    {field_name::kAffine, "/frames/C", 9, "Tensor", true, kF64},
    {field_name::kDeformation, "/frames/F", 9, "Tensor", true, kF64},
    {field_name::kStress, "/frames/tau", 6, "Matrix", true, kF64},
    {field_name::kRestPosition, "/X", 3, "Vector", false, kF64},
    {field_name::kMass, "/mass", 1, "Scalar", false, kF64},
    {field_name::kVolume, "/volume", 1, "Scalar", false, kF64},
    {field_name::kMaterial, "/material", 1, "Scalar", false, kU16},
    {field_name::kObject, "/object", 1, "Scalar", false, kU16},
};

std::string dims(size_t a, size_t width) {
  return width == 1 ? std::to_string(a) : std::to_string(a) + " " + std::to_string(width);
}

// Frame `k` of a per-frame dataset [frames, P, width], as a hyperslab.
void frame_item(std::ostream& x, const std::string& file, const char* dataset, size_t k,
                size_t frames, size_t p, size_t width, const char* number, const char* indent) {
  x << indent << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << dims(p, width)
    << "\" Type=\"HyperSlab\">\n"
    << indent << "  <DataItem Dimensions=\"3 3\" Format=\"XML\">" << k << " 0 0 1 1 1 1 " << p
    << " " << width << "</DataItem>\n"
    << indent << "  <DataItem Dimensions=\"" << frames << " " << p << " " << width << "\" "
    << number << " Format=\"HDF\">" << file << ":" << dataset << "</DataItem>\n"
    << indent << "</DataItem>\n";
}

}  // namespace

std::string run_xdmf(const std::string& h5_name, size_t particles,
                     const std::vector<double>& times) {
  const std::string file = xml_escape(h5_name);
  const size_t frames = times.size(), p = particles;
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n"
    << "<!-- The XDMF sidecar of an nsf run file (docs/OUTPUT.md). Each frame reads\n"
    << "     hyperslabs of the run file's datasets, for the Xdmf (2) readers of ParaView and\n"
    << "     VisIt. Readers that read no hyperslabs (meshio) or read them transposed (the Xdmf3\n"
    << "     library) read the files of `nsf export RUN.h5 -f xdmf -o DIR` instead. -->\n"
    << "<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n  <Domain>\n"
    << "    <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < frames; ++k) {
    x << "      <Grid Name=\"frame_" << k << "\" GridType=\"Uniform\">\n"
      << "        <Time Value=\"" << num(times[k]) << "\"/>\n";
    // Particle i is vertex i. The connectivity is written out once, in the first frame, and the
    // other frames include that topology: the run file holds no such dataset, and without one the
    // Xdmf3 library (so ParaView's XDMF3 readers) makes no cells of a Polyvertex topology.
    if (k == 0) {
      x << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << p
        << "\" NodesPerElement=\"1\">\n"
        << "          <DataItem Dimensions=\"" << p
        << "\" NumberType=\"Int\" Precision=\"4\" Format=\"XML\">";
      for (size_t i = 0; i < p; ++i) x << (i % 16 == 0 ? "\n            " : " ") << i;
      x << "\n          </DataItem>\n        </Topology>\n";
    } else {
      x << "        <xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/Topology)\"/>\n";
    }
    x << "        <Geometry GeometryType=\"XYZ\">\n";
    frame_item(x, file, "/frames/x", k, frames, p, 3, kF64, "          ");
    x << "        </Geometry>\n";
    for (const Field& f : kFields) {
      x << "        <Attribute Name=\"" << f.name << "\" AttributeType=\"" << f.type
        << "\" Center=\"Node\">\n";
      if (f.per_frame) {
        frame_item(x, file, f.dataset, k, frames, p, f.width, f.number, "          ");
      } else {
        x << "          <DataItem Dimensions=\"" << dims(p, f.width) << "\" " << f.number
          << " Format=\"HDF\">" << file << ":" << f.dataset << "</DataItem>\n";
      }
      x << "        </Attribute>\n";
    }
    x << "      </Grid>\n";
  }
  x << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return x.str();
}

std::string xdmf_path_for(const std::string& run_path) {
  std::filesystem::path p(run_path);
  return p.replace_extension(".xdmf").string();
}

}  // namespace nsf
