# SPDX-License-Identifier: AGPL-3.0-or-later
find_package(nlohmann_json 3.10 REQUIRED)
