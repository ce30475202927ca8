// Which share of a sweep this process runs: its rank among the processes `mpirun` started (read
// from the launcher's environment, so romp needs no MPI library), or rank 0 of 1 otherwise.
#pragma once

#include <map>
#include <string>

namespace romp::run {

struct ProcessRank {
  int rank = 0;
  int size = 1;
  std::string launcher;  // "OpenMPI", "PMI" (MPICH, Intel MPI, Slurm), or "" when not launched by one
};

// Reads OMPI_COMM_WORLD_RANK/SIZE (OpenMPI) or PMI_RANK/PMI_SIZE from `environment`; a malformed or
// inconsistent pair is a romp::Error.
ProcessRank detect_process_rank(const std::map<std::string, std::string>& environment);
ProcessRank detect_process_rank();

}  // namespace romp::run
