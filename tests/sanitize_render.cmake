# Included by ctest after the discovered tests are defined (sanitizer builds only).
if(TEST Render.OsmesaAndEglDrawTheSameImage)
  set_tests_properties(Render.OsmesaAndEglDrawTheSameImage PROPERTIES
                       ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
