# SPDX-License-Identifier: AGPL-3.0-or-later
# Open MPI (Debian's libopenmpi-dev): a cohort design spread over processes,
# launched by mpirun or srun (core/ranks.hpp).
palpa_find_package(MPI COMPONENTS CXX)
