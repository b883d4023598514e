# Imported target gdcm::gdcm: GDCM's DICOM reading, writing and codecs (its MSFF library), visible
# in every directory: the DICOM reader in src/ links it, and tests/ writes DICOM files with it.
# Debian: libgdcm-dev. Its GDCMConfig.cmake can also describe GDCM's VTK module, which mvox does
# not use.
set(GDCM_SKIP_USE_VTK ON)
find_package(GDCM 3.0 REQUIRED CONFIG)
if(NOT TARGET gdcm::gdcm)
  add_library(gdcm::gdcm INTERFACE IMPORTED GLOBAL)
  target_link_libraries(gdcm::gdcm INTERFACE gdcmMSFF)
endif()
