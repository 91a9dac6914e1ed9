#pragma once
// The messages of `nsf serve` (docs/SERVE.md): the model message a client receives once, the
// frame message it receives per frame, and the commands it may send. Binary messages are
// little-endian; the server writes them on a little-endian machine (checked at compile time).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "nn/basis_decoders.h"

namespace nsf::app {

// "NSFM", uint32 H, H bytes of JSON (padded with spaces to a multiple of 4), then the float32
// arrays the JSON's "arrays" list names, each at its byte "offset" from the message's start:
// rest (P × 3), mean (P × 3) and the leading `modes_here` modes of the deformation basis (P × 3 ×
// modes_here). The JSON's "modes" is K, every mode; basis messages bring the others. `info` is
// merged into the JSON (scene, colliders, frame time, ...). With rigid frames (rom.rigid_frames),
// `rigid_frame` holds each particle's (−1: none) and goes as the float32 array "frame" (P), and the
// JSON's "rigid_frames" counts them.
std::string model_message(const BasisDecoders& bases, const nlohmann::json& info, int modes_here,
                          const std::vector<int>& rigid_frame = {});

// "NSFB", uint32 first mode k0, uint32 modes n, uint32 P, then float32 P × 3 × n (particle,
// component, mode k0 … k0 + n − 1): more of the basis, after the model message. 16 + 12·P·n bytes.
std::string basis_message(const BasisDecoders& bases, int first, int count);
constexpr size_t kBasisHeaderBytes = 16;
// How many modes of P particles one message of about `bytes` holds (at least 1).
int modes_per_message(size_t particles, size_t bytes);

// A collider's pose as streamed: its reference point and its rotation (row-major, body → world).
using StreamPose = std::array<float, 12>;
StreamPose stream_pose(const Vec3& position, const Mat3& rotation);

// "NSFF", uint32 frame, float64 time, float64 sent (the server's wall clock, Unix seconds),
// uint32 r, uint32 K, uint32 colliders, float32 the error indicator of the frame's last step
// (rom/step/step_guard.h: below 1 fine); then r float64 ẑ, K float32 c = c_x(ẑ), 12 float32 per
// collider (position, rotation), and 12 per rigid frame (offset o, rotation R: a particle of the
// frame is at R y + o, y what the basis gives). 40 + 8r + 4K + 48·(colliders + rigid frames)
// bytes.
std::string frame_message(uint32_t frame, double time, double sent, const Eigen::VectorXd& z,
                          const Eigen::VectorXf& c, const std::vector<StreamPose>& poses,
                          float indicator = 0, const std::vector<StreamPose>& rigid = {});
constexpr size_t kFrameHeaderBytes = 40;

// What a client decodes (the reference client: tests, tools).
struct StreamModel {
  nlohmann::json header;
  int K = 0;
  int received = 0;  // the leading modes received so far (K: the whole basis)
  std::vector<float> rest, mean;
  std::vector<float> modes;  // P × 3 × K; the modes not yet received are zeros
  std::vector<float> frame;  // each particle's rigid frame (−1: none); empty: no frames
};
struct StreamFrame {
  uint32_t frame = 0;
  double time = 0, sent = 0;
  float indicator = 0;
  std::vector<double> z;
  std::vector<float> c;
  std::vector<StreamPose> poses;
  std::vector<StreamPose> rigid;  // the rigid frames' maps, as many as the model's "rigid_frames"
};
// nullopt when the bytes are not such a message.
std::optional<StreamModel> decode_model(const std::string& bytes);
std::optional<StreamFrame> decode_frame(const std::string& bytes);
// Adds a basis message's modes to `model`; false (and `model` unchanged) when the bytes are not
// such a message or not the next modes of this model.
bool add_basis(StreamModel& model, const std::string& bytes);
// x_p = rest_p + (mean_p + modes_p · c), in float32 as a client computes it (P × 3), with the
// modes received so far; a particle in rigid frame f then moves to R_f x_p + o_f (`rigid`: the
// frame message's).
std::vector<float> reconstruct(const StreamModel& model, const std::vector<float>& c,
                               const std::vector<StreamPose>& rigid = {});

// A client's command, a JSON text message:
//   {"type": "move", "collider": i, "position": [x, y, z]}      (optional "rotation": 9 numbers)
//   {"type": "reset"}                                             (back to the scene's start)
struct ServeCommand {
  enum Kind { move, reset } kind = move;
  size_t collider = 0;
  Vec3 position = Vec3::Zero();
  std::optional<Mat3> rotation;
};
// Throws nsf::Error saying what is wrong (not JSON, an unknown type or key, a collider that does
// not exist, a value that is not finite, a rotation that is not one).
ServeCommand parse_command(const std::string& text, size_t collider_count);

}  // namespace nsf::app
