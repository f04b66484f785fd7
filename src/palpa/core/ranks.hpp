// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The processes one run is spread over: MPI's world when palpa was launched
// by mpirun or srun (Open MPI), else this process alone (rank 0 of 1, and no
// MPI at all: a plain run starts no MPI runtime).
//
// A cohort design (design/optimizer.hpp) puts each body on one rank and
// sends what the others need as bytes from it: every rank then takes the same
// steps on the same numbers, and rank 0 alone writes files.

#include <string>

namespace palpa::ranks {

// Starts MPI when the environment says an MPI launcher started this process
// (OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_RANK set); otherwise nothing.
// Call once, first thing in main. Throws palpa::Error (Internal) when MPI
// cannot start.
void init(int& argc, char**& argv);
// Ends MPI (a no-op without it). A rank that stops on an error (a non-zero
// exit code) takes the others down with it, with that code, rather than
// leaving them waiting.
void finalize(int exit_code = 0);

int rank() noexcept;  // 0 …  size() − 1
int size() noexcept;  // 1 without MPI
bool is_root() noexcept;

// `bytes` from rank `root` to every rank (resized on the others).
void broadcast(std::string& bytes, int root);
// A flag every rank gets from `root`.
bool broadcast_flag(bool value, int root);

}  // namespace palpa::ranks
