# SPDX-License-Identifier: AGPL-3.0-or-later
find_package(spdlog REQUIRED)
