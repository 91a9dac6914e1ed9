#pragma once
// Checks on what a model file holds, before and after the loader (nn/model/model_file.cpp) uses it.
// Model files are passed between people, and a checksum only shows that a file is as written, not
// that it was written by nsf: a hostile or damaged file with a matching checksum must still be
// refused with a message naming the entry, never crash the tool or make it allocate terabytes.
#include <torch/nn/module.h>
#include <torch/serialize/archive.h>

#include <cstdint>
#include <string>

#include "nn/config.h"

namespace nsf {

// A size entry of the configuration (latent_dim, a width, a depth, a mode count): 1 to INT_MAX.
int model_size_entry(int64_t value, const std::string& key, const std::string& path);

// The 16 hex digits of the scene's X hash.
uint64_t model_hash_entry(const std::string& text, const std::string& path);

// Refuses a configuration whose networks and bases need more float32 numbers than the file has
// bytes (`file_bytes`; 0: not checked): nothing nsf wrote is that small, and the loader would
// otherwise allocate whatever a file asks for before it reads a single weight.
void check_model_fits_file(const NetConfig& c, int64_t particles, bool stress_uses_mu,
                           uintmax_t file_bytes, const std::string& path);

// A float32 tensor entry of exactly `shape` whose values are all finite.
void check_model_tensor(const torch::Tensor& t, at::IntArrayRef shape, const std::string& key,
                        const std::string& path);

// net->load(archive) that refuses weights whose shapes or types differ from those the
// configuration built (torch's own load would take them and fail later, mid-evaluation), and
// weights that are not finite (they would reach the ROM's inversion as a NaN latent).
void load_network_checked(torch::nn::Module& net, torch::serialize::InputArchive& archive,
                          const std::string& name, const std::string& path);

}  // namespace nsf
