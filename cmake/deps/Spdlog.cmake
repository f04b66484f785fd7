# SPDX-License-Identifier: AGPL-3.0-or-later
palpa_find_package(spdlog)
