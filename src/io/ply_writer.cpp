#include "io/ply_writer.h"

#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/binary_out.h"
#include "io/colormap.h"

namespace nsf {

void write_ply(const std::string& path, const RunFrame& f, const std::vector<uint16_t>& material,
               const std::vector<uint16_t>& object, const PlyOptions& options) {
  const size_t n = f.x.size();
  if (f.v.size() != n || f.tau.size() != n || material.size() != n || object.size() != n)
    fail(path, ": frame arrays of different lengths");
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
  for (const char* p : {"vx", "vy", "vz", "speed", "von_mises"})
    h << "property float32 " << p << "\n";
  h << "property uint16 material\nproperty uint16 object\nend_header\n";

  std::string buf = h.str();
  buf.reserve(buf.size() + n * (3 * (options.double_positions ? 8 : 4) + 5 * 4 + 2 * 2));
  for (size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (options.double_positions) {
        put_le(buf, f.x[i][a]);
      } else {
        put_le(buf, static_cast<float>(f.x[i][a]));
      }
    }
    for (int a = 0; a < 3; ++a) put_le(buf, static_cast<float>(f.v[i][a]));
    put_le(buf, static_cast<float>(f.v[i].norm()));
    put_le(buf, static_cast<float>(von_mises(f.tau[i])));
    put_le(buf, material[i]);
    put_le(buf, object[i]);
  }
  write_file_atomic(path, buf);
}

}  // namespace nsf
