# SPDX-License-Identifier: AGPL-3.0-or-later
palpa_find_package(nlohmann_json 3.10)
