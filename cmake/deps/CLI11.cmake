# SPDX-License-Identifier: AGPL-3.0-or-later
find_package(CLI11 2.1 REQUIRED)
