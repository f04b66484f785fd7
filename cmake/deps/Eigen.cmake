# SPDX-License-Identifier: AGPL-3.0-or-later
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
