#pragma once
// MPI's C interface for the app layer's process teams (sweep_ranks.cpp, train_team.cpp), when
// CMake builds with MPI (it sets NSF_WITH_MPI=1 on those files; -DNSF_WITH_MPI=OFF leaves it out).
#if NSF_WITH_MPI
// The C interface only: MPI's C++ bindings (gone from the standard) need another library.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <string>

#include "core/error.h"

namespace nsf::app {

// Throws nsf::Error ("MPI: what: MPI's own message") unless `code` is MPI_SUCCESS.
inline void check_mpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  fail("MPI: ", what, ": ", std::string(text, size_t(length)));
}

}  // namespace nsf::app
#endif
