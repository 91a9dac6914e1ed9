#pragma once
// Reads a run file written by RunWriter (layout: docs/OUTPUT.md). The constructor validates the
// whole layout up front, so a foreign, truncated or half-written file fails at open with a message
// naming the file and the problem, not later in the middle of training or rendering.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

// One saved frame, unpacked: C and F back to matrices, τ back to a symmetric matrix.
struct RunFrame {
  double time = 0;
  std::vector<Vec3> x, v;
  std::vector<Mat3> C, F, tau;
};

class RunReader {
 public:
  explicit RunReader(const std::string& path);
  ~RunReader();
  RunReader(RunReader&&) noexcept;
  RunReader& operator=(RunReader&&) noexcept;
  RunReader(const RunReader&) = delete;
  RunReader& operator=(const RunReader&) = delete;

  const std::string& path() const;
  size_t particle_count() const;
  size_t frame_count() const;

  // The standard attributes, read and checked at open.
  int format_version() const;
  const std::string& nsf_version() const;
  const std::string& scene_name() const;
  const std::string& scene_json() const;
  double dt() const;
  double dx() const;
  int substeps() const;

  // Any root attribute, including ones added with RunWriter::set_attribute ("mu"). Fail with the
  // file and attribute name when it is missing or of another kind.
  bool has_attribute(const std::string& name) const;
  double attribute_double(const std::string& name) const;  // also accepts integer attributes
  int64_t attribute_int(const std::string& name) const;
  std::string attribute_string(const std::string& name) const;

  // Static per-particle data, indexed by particle.
  const std::vector<Vec3>& rest_positions() const;  // /X
  const std::vector<double>& mass() const;
  const std::vector<double>& volume() const;
  const std::vector<uint16_t>& material() const;
  const std::vector<uint16_t>& object() const;
  const std::vector<double>& times() const;  // one per frame

  // The root attributes by name (the standard ones included), alphabetically; the kind of one.
  enum class AttributeKind { Integer, Float, String, Other };
  std::vector<std::string> attribute_names() const;
  AttributeKind attribute_kind(const std::string& name) const;

  RunFrame read_frame(size_t k) const;
  // Every frame of one per-frame dataset, "x", "v", "C", "F" or "tau", as stored (frames ×
  // particles × frame_field_width(field) doubles; C and F row-major, τ as run_format::kSymOrder),
  // read straight into out[0, size): one read, no copy. Fails naming the file when the field is
  // unknown or `size` is not that count.
  static size_t frame_field_width(const std::string& field);
  void read_all_frames(const std::string& field, double* out, size_t size) const;
  // Only x: the cheap read for rendering and for comparing trajectories (δ).
  std::vector<Vec3> read_positions(size_t k) const;
  // One per-frame dataset of frame k, as stored (particles × frame_field_width(field) doubles):
  // what a reader that needs one field of a large run reads instead of the whole frame.
  std::vector<double> read_frame_field(size_t k, const std::string& field) const;

  // A two-dimensional table beside the frames (RunWriter::write_table, e.g. "/rom/latent"):
  // rows × cols doubles, row-major. Fails naming the file when it is missing or not 2-D.
  std::vector<double> read_table(const std::string& name, size_t& rows, size_t& cols) const;
  bool has_dataset(const std::string& name) const;  // e.g. "/rom/latent"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nsf
