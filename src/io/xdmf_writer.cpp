#include "io/xdmf_writer.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "io/xml_escape.h"

namespace nsf {

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

struct Field {
  const char* name;  // attribute name in ParaView
  const char* dataset;
  size_t width;      // components per particle
  const char* type;  // XDMF AttributeType
  bool per_frame;
  const char* number;  // NumberType and Precision
};

// tau is stored xx yy zz xy yz xz, not in XDMF's Tensor6 order (xx xy xz yy yz zz), so it is a
// plain 6-component "Matrix" attribute.
const Field kFields[] = {
    {"v", "/frames/v", 3, "Vector", true, "NumberType=\"Float\" Precision=\"8\""},
    {"C", "/frames/C", 9, "Tensor", true, "NumberType=\"Float\" Precision=\"8\""},
    {"F", "/frames/F", 9, "Tensor", true, "NumberType=\"Float\" Precision=\"8\""},
    {"tau", "/frames/tau", 6, "Matrix", true, "NumberType=\"Float\" Precision=\"8\""},
    {"X", "/X", 3, "Vector", false, "NumberType=\"Float\" Precision=\"8\""},
    {"mass", "/mass", 1, "Scalar", false, "NumberType=\"Float\" Precision=\"8\""},
    {"volume", "/volume", 1, "Scalar", false, "NumberType=\"Float\" Precision=\"8\""},
    {"material", "/material", 1, "Scalar", false, "NumberType=\"UInt\" Precision=\"2\""},
    {"object", "/object", 1, "Scalar", false, "NumberType=\"UInt\" Precision=\"2\""},
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
  const char* f64 = "NumberType=\"Float\" Precision=\"8\"";
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n"
    << "<Xdmf Version=\"3.0\">\n  <Domain>\n"
    << "    <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < frames; ++k) {
    x << "      <Grid Name=\"frame_" << k << "\" GridType=\"Uniform\">\n"
      << "        <Time Value=\"" << num(times[k]) << "\"/>\n"
      << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << p
      << "\" NodesPerElement=\"1\"/>\n"
      << "        <Geometry GeometryType=\"XYZ\">\n";
    frame_item(x, file, "/frames/x", k, frames, p, 3, f64, "          ");
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
