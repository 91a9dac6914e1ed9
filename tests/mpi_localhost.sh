# Sourced by tests/check_mpi_*.sh: a scratch folder removed on exit (with the mpirun left running
# in $mpirun_pid, if any), die and step, and Open MPI set up for two processes on this machine.
# Expects $check (the script's name for messages); sets $tmp, $mpirun_pid.
tmp=$(mktemp -d "${TMPDIR:-/tmp}/nsf_${check}.XXXXXX")
mpirun_pid=""
cleanup() {
  if [[ -n "$mpirun_pid" ]]; then kill -9 "$mpirun_pid" 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
die() {
  echo "$check: $*" >&2
  exit 1
}
step() { echo "== $* ($SECONDS s)"; }

# Open MPI refuses to run as root unless told; a container has no cross-memory attach for the
# shared-memory transport and may have fewer cores than processes (--oversubscribe); binding
# each process to one core is left to the cluster.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none
