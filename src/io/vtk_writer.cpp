#include "io/vtk_writer.h"

#include <cstdio>
#include <functional>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/binary_out.h"
#include "io/frame_fields.h"
#include "io/xml_escape.h"

namespace nsf {

namespace {

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

}  // namespace

void write_vtk_legacy(const std::string& path, const RunFrame& f,
                      const std::vector<uint16_t>& material, const std::vector<uint16_t>& object,
                      const VtkFrameInfo& info) {
  const std::vector<FrameField> fields = frame_fields(f, material, object, path);
  const size_t n = f.x.size();
  std::string title = info.title.substr(0, 255);  // the format's limit for the title line
  for (char& c : title)
    if (c == '\n' || c == '\r') c = ' ';
  std::string b = "# vtk DataFile Version 3.0\n" + title + "\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  b += "FIELD FieldData 1\nTIME 1 1 double\n";
  put_be(b, info.time);
  b += "\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& p : f.x)
    for (int a = 0; a < 3; ++a) put_be(b, p[a]);
  // One VTK_VERTEX (type 1) cell per particle, as in the VTU files.
  b += "\nCELLS " + std::to_string(n) + " " + std::to_string(2 * n) + "\n";
  for (size_t i = 0; i < n; ++i) {
    put_be(b, int32_t{1});
    put_be(b, static_cast<int32_t>(i));
  }
  b += "\nCELL_TYPES " + std::to_string(n) + "\n";
  for (size_t i = 0; i < n; ++i) put_be(b, int32_t{1});
  // Field arrays, not SCALARS / VECTORS / TENSORS sections: of those VTK's legacy readers keep only
  // the first of each kind unless told otherwise, while every field array reaches every reader.
  b += "\nPOINT_DATA " + std::to_string(n) + "\nFIELD FieldData " + std::to_string(fields.size()) +
       "\n";
  for (const FrameField& field : fields) {
    b += std::string(field.name) + " " + std::to_string(field.components) + " " +
         std::to_string(n) + (field.index ? " unsigned_short\n" : " double\n");
    if (field.index) {
      for (uint16_t v : field.indices) put_be(b, v);
    } else {
      for (double v : field.values) put_be(b, v);
    }
    b += "\n";
  }
  write_file_atomic(path, b);
}

void write_vtu(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
               const std::vector<uint16_t>& object, const VtkFrameInfo& info) {
  const std::vector<FrameField> fields = frame_fields(f, material, object, path);
  const size_t n = f.x.size();

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
  xml << "      <PointData Scalars=\"" << field_name::kVonMises << "\" Vectors=\""
      << field_name::kVelocity << "\" Tensors=\"" << field_name::kStress << "\">\n";
  for (const FrameField& field : fields) {
    array(field.index ? "UInt16" : "Float64", field.name, field.components, [&](std::string& d) {
      if (field.index) {
        for (uint16_t v : field.indices) put_le(d, v);
      } else {
        for (double v : field.values) put_le(d, v);
      }
    });
  }
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
