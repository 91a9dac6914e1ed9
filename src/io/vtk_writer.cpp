#include "io/vtk_writer.h"

#include <cstdio>
#include <functional>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/binary_out.h"
#include "io/colormap.h"
#include "io/xml_escape.h"

namespace nsf {

namespace {

void check_sizes(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
                 const std::vector<uint16_t>& object) {
  const size_t n = f.x.size();
  if (f.v.size() != n || f.tau.size() != n || f.F.size() != n || material.size() != n ||
      object.size() != n)
    fail(path, ": frame arrays of different lengths");
}

// Full precision, so that a value read back is the value written.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

// Row-major, like /frames/F in the run file and as VTK expects tensors.
template <typename Put>
void put_matrix(std::string& buf, const Mat3& m, Put put) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) put(buf, m(i, j));
}

}  // namespace

void write_vtk_legacy(const std::string& path, const RunFrame& f,
                      const std::vector<uint16_t>& material, const std::vector<uint16_t>& object,
                      const VtkFrameInfo& info) {
  check_sizes(path, f, material, object);
  const size_t n = f.x.size();
  const auto be = [](std::string& b, auto v) { put_be(b, v); };
  std::string title = info.title.substr(0, 255);  // the format's limit for the title line
  for (char& c : title)
    if (c == '\n' || c == '\r') c = ' ';
  std::string b = "# vtk DataFile Version 3.0\n" + title + "\nBINARY\nDATASET POLYDATA\n";
  b += "FIELD FieldData 1\nTIME 1 1 double\n";
  put_be(b, info.time);
  b += "\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& p : f.x)
    for (int a = 0; a < 3; ++a) put_be(b, p[a]);
  b += "\nVERTICES " + std::to_string(n) + " " + std::to_string(2 * n) + "\n";
  for (size_t i = 0; i < n; ++i) {
    put_be(b, int32_t{1});
    put_be(b, static_cast<int32_t>(i));
  }
  b += "\nPOINT_DATA " + std::to_string(n) + "\nVECTORS velocity double\n";
  for (const Vec3& v : f.v)
    for (int a = 0; a < 3; ++a) put_be(b, v[a]);
  b += "\nSCALARS speed double 1\nLOOKUP_TABLE default\n";
  for (const Vec3& v : f.v) put_be(b, v.norm());
  b += "\nSCALARS von_mises double 1\nLOOKUP_TABLE default\n";
  for (const Mat3& t : f.tau) put_be(b, von_mises(t));
  b += "\nTENSORS tau double\n";
  for (const Mat3& t : f.tau) put_matrix(b, t, be);
  b += "\nTENSORS F double\n";
  for (const Mat3& F : f.F) put_matrix(b, F, be);
  b += "\nSCALARS material unsigned_short 1\nLOOKUP_TABLE default\n";
  for (uint16_t m : material) put_be(b, m);
  b += "\nSCALARS object unsigned_short 1\nLOOKUP_TABLE default\n";
  for (uint16_t o : object) put_be(b, o);
  b += "\n";
  write_file_atomic(path, b);
}

void write_vtu(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
               const std::vector<uint16_t>& object, const VtkFrameInfo& info) {
  check_sizes(path, f, material, object);
  const size_t n = f.x.size();
  const auto le = [](std::string& b, auto v) { put_le(b, v); };

  // Each array is a block of the appended section: a UInt64 byte count, then the raw values.
  std::string appended;
  std::ostringstream xml;
  const auto array = [&](const char* type, const char* name, int components,
                         const std::function<void(std::string&)>& fill) {
    xml << "        <DataArray type=\"" << type << "\" Name=\"" << name
        << "\" NumberOfComponents=\"" << components << "\" format=\"appended\" offset=\""
        << appended.size() << "\"/>\n";
    std::string data;
    fill(data);
    put_le(appended, static_cast<uint64_t>(data.size()));
    appended += data;
  };

  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <FieldData>\n";
  xml << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
         "format=\"ascii\">"
      << num(info.time) << "</DataArray>\n    </FieldData>\n";
  xml << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n";
  xml << "      <PointData Scalars=\"von_mises\" Vectors=\"velocity\" Tensors=\"tau\">\n";
  array("Float64", "velocity", 3, [&](std::string& d) {
    for (const Vec3& v : f.v)
      for (int a = 0; a < 3; ++a) put_le(d, v[a]);
  });
  array("Float64", "speed", 1, [&](std::string& d) {
    for (const Vec3& v : f.v) put_le(d, v.norm());
  });
  array("Float64", "von_mises", 1, [&](std::string& d) {
    for (const Mat3& t : f.tau) put_le(d, von_mises(t));
  });
  array("Float64", "tau", 9, [&](std::string& d) {
    for (const Mat3& t : f.tau) put_matrix(d, t, le);
  });
  array("Float64", "F", 9, [&](std::string& d) {
    for (const Mat3& F : f.F) put_matrix(d, F, le);
  });
  array("UInt16", "material", 1, [&](std::string& d) {
    for (uint16_t m : material) put_le(d, m);
  });
  array("UInt16", "object", 1, [&](std::string& d) {
    for (uint16_t o : object) put_le(d, o);
  });
  xml << "      </PointData>\n      <Points>\n";
  array("Float64", "Points", 3, [&](std::string& d) {
    for (const Vec3& p : f.x)
      for (int a = 0; a < 3; ++a) put_le(d, p[a]);
  });
  xml << "      </Points>\n      <Cells>\n";
  // One VTK_VERTEX (type 1) cell per particle: ParaView then draws and filters them as points.
  array("Int64", "connectivity", 1, [&](std::string& d) {
    for (size_t i = 0; i < n; ++i) put_le(d, static_cast<int64_t>(i));
  });
  array("Int64", "offsets", 1, [&](std::string& d) {
    for (size_t i = 0; i < n; ++i) put_le(d, static_cast<int64_t>(i + 1));
  });
  array("UInt8", "types", 1, [&](std::string& d) { d.append(n, '\1'); });
  xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n"
      << "  <AppendedData encoding=\"raw\">\n   _";

  AtomicFile out(path);
  const std::string head = xml.str();
  out.stream().write(head.data(), static_cast<std::streamsize>(head.size()));
  out.stream().write(appended.data(), static_cast<std::streamsize>(appended.size()));
  out.stream() << "\n  </AppendedData>\n</VTKFile>\n";
  out.commit();
}

void write_pvd(const std::string& path, const std::vector<SeriesEntry>& entries) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
       "byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const SeriesEntry& e : entries)
    x << "    <DataSet timestep=\"" << num(e.time) << "\" group=\"\" part=\"0\" file=\""
      << xml_escape(e.file) << "\"/>\n";
  x << "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, x.str());
}

void write_vtk_series(const std::string& path, const std::vector<SeriesEntry>& entries) {
  std::ostringstream j;
  j << "{\n  \"file-series-version\": \"1.0\",\n  \"files\": [\n";
  for (size_t i = 0; i < entries.size(); ++i)
    j << "    {\"name\": \"" << json_escape(entries[i].file)
      << "\", \"time\": " << num(entries[i].time) << "}" << (i + 1 < entries.size() ? "," : "")
      << "\n";
  j << "  ]\n}\n";
  write_file_atomic(path, j.str());
}

}  // namespace nsf
