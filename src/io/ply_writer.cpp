#include "io/ply_writer.h"

#include <sstream>

#include "io/atomic_file.h"
#include "io/binary_out.h"
#include "io/frame_fields.h"

namespace nsf {

namespace {

const char* const kAxes[] = {"_x", "_y", "_z"};

}  // namespace

void write_ply(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
               const std::vector<uint16_t>& object, const PlyOptions& options) {
  const std::vector<FrameField> all = frame_fields(f, material, object, path);
  // PLY holds scalars: the vectors go component by component, the tensors (tau, F) stay out.
  std::vector<const FrameField*> fields;
  for (const FrameField& field : all)
    if (field.components == 1 || field.components == 3) fields.push_back(&field);
  const size_t n = f.x.size();
  // Type names that meshio (7.0 reads binary PLY with uint16, float32 and double, but not ushort
  // or float64) and VTK, Blender and Houdini all read.
  const char* pos_type = options.double_positions ? "double" : "float32";
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n";
  if (!options.comment.empty()) {
    std::string line = options.comment;  // a line break would end the comment mid-header
    for (char& c : line)
      if (c == '\n' || c == '\r') c = ' ';
    h << "comment " << line << "\n";
  }
  h << "element vertex " << n << "\n";
  for (const char* p : {"x", "y", "z"}) h << "property " << pos_type << " " << p << "\n";
  size_t vertex_bytes = 3 * (options.double_positions ? 8 : 4);
  for (const FrameField* field : fields) {
    const char* type = field->index ? "uint16" : "float32";
    for (int c = 0; c < field->components; ++c)
      h << "property " << type << " " << field->name << (field->components == 3 ? kAxes[c] : "")
        << "\n";
    vertex_bytes += static_cast<size_t>(field->components) * (field->index ? 2 : 4);
  }
  h << "end_header\n";

  std::string buf = h.str();
  buf.reserve(buf.size() + n * vertex_bytes);
  for (size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (options.double_positions) {
        put_le(buf, f.x[i][a]);
      } else {
        put_le(buf, static_cast<float>(f.x[i][a]));
      }
    }
    for (const FrameField* field : fields) {
      const size_t w = static_cast<size_t>(field->components);
      for (size_t c = 0; c < w; ++c) {
        if (field->index) {
          put_le(buf, field->indices[i * w + c]);
        } else {
          put_le(buf, static_cast<float>(field->values[i * w + c]));
        }
      }
    }
  }
  write_file_atomic(path, buf);
}

}  // namespace nsf
