# SPDX-License-Identifier: AGPL-3.0-or-later
# zlib: compressed VTU arrays (vtkZLibDataCompressor), Debian's zlib1g-dev.
palpa_find_package(ZLIB)
