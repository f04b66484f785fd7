# SPDX-License-Identifier: AGPL-3.0-or-later
# Debian's Ceres names the BLAS it was built with, ATLAS, by its own files
# (libf77blas, libatlas) besides the generic libblas/liblapack. Linked in, they
# come before libblas.so.3 in the program's search order, so ATLAS's dgemm would
# serve every caller, CHOLMOD included, whatever BLAS Debian's alternatives
# select. Keep only the generic libraries: libblas.so.3 and liblapack.so.3 are
# then whichever implementation is installed with the highest priority
# (OpenBLAS, see scripts/setup.sh), and `palpa --version` names it.
# BLA_VENDOR=Generic makes FindBLAS (called by Ceres's configuration for the
# BLAS::BLAS and LAPACK::LAPACK targets) choose those; Ceres's own target lists
# the files it was built with, which are filtered out below. BLA_VENDOR is
# restored afterwards, so that the choice does not reach a project that finds
# an installed palpa.
set(_palpa_bla_vendor_set FALSE)
if(DEFINED BLA_VENDOR)
  set(_palpa_bla_vendor_set TRUE)
  set(_palpa_bla_vendor "${BLA_VENDOR}")
endif()
set(BLA_VENDOR Generic)
palpa_find_package(Ceres 2.1)
if(_palpa_bla_vendor_set)
  set(BLA_VENDOR "${_palpa_bla_vendor}")
else()
  unset(BLA_VENDOR)
endif()
unset(_palpa_bla_vendor_set)
unset(_palpa_bla_vendor)
get_target_property(_palpa_ceres_links Ceres::ceres INTERFACE_LINK_LIBRARIES)
if(NOT _palpa_ceres_links)
  set(_palpa_ceres_links)
endif()
set(_palpa_ceres_kept)
foreach(_lib IN LISTS _palpa_ceres_links)
  if(_lib MATCHES "/lib(f77blas|cblas|atlas|satlas|tatlas)\\.(so|a)$")
    continue()
  endif()
  list(APPEND _palpa_ceres_kept "${_lib}")
endforeach()
set_target_properties(Ceres::ceres PROPERTIES INTERFACE_LINK_LIBRARIES "${_palpa_ceres_kept}")
unset(_palpa_ceres_links)
unset(_palpa_ceres_kept)
