#pragma once
// A reduced-order run that cannot go on: its latent dynamics diverged (a point it integrates left
// the grid or stopped being finite), or its step is past the bound its explicit stress allows
// (the tracked state's CFL bound). A search over settings (rom/calibration) rules a setting out
// on this error, and only on it: any other failure, a scene the engine refuses say, is the
// caller's to see.
#include <sstream>

#include "core/error.h"

namespace nsf {

class RomDiverged : public Error {
 public:
  using Error::Error;
};

// Throws RomDiverged with a message built as fail() builds one.
template <typename... Args>
[[noreturn]] void fail_diverged(const Args&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  throw RomDiverged(os.str());
}

}  // namespace nsf
