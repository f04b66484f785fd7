# SPDX-License-Identifier: AGPL-3.0-or-later
palpa_find_package(Eigen3 3.4 NO_MODULE)
