#pragma once
// The positions render and export accept from a run file. The engine stops a simulation that
// blows up, so a NaN, an infinity or a particle a thousand kilometres away means a damaged or
// foreign file, and passing it on gives endless camera fits and NaN-filled output files.
#include <cstddef>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

// |x|, |y| and |z| of a particle must not exceed this, in metres.
constexpr double kMaxRunCoordinate = 1e6;

// Fails, naming `path`, the frame and the first bad particle with its position, unless every
// coordinate is finite and within kMaxRunCoordinate.
void check_run_positions(const std::vector<Vec3>& x, const std::string& path, size_t frame);

}  // namespace nsf
