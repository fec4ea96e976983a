# The installed package (issue 21): `cmake --install BUILD --prefix P` puts
# the libraries, the public headers and the `surfreg` program under P, and
# find_package(surfreg CONFIG) then gives
#   surfreg::measure       geometry and measures          (surfreg_measure)
#   surfreg::registration  Ceres costs and aligners       (surfreg_registration)
#   surfreg::faces         face frame, asymmetry, jaw     (surfreg_faces)
#   surfreg::terrain       frames, change budgets, tiles  (surfreg_terrain)
#   surfreg::io            surface, mesh and raster files (surfreg_io)
# In-tree the same names are ALIASes, so code built here or against the
# install links the same way.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

foreach(layer measure registration faces io terrain)
  add_library(surfreg::${layer} ALIAS surfreg_${layer})
  set_target_properties(surfreg_${layer} PROPERTIES EXPORT_NAME ${layer})
endforeach()
# Our headers need C++17: a client gets it from the targets.
target_compile_features(surfreg_measure PUBLIC cxx_std_17)

# Public headers: what a client of Measure, Align and the readers includes,
# plus exactly the headers those include (tests/cli_install_test.sh compiles
# each installed header on its own against the install, and checks that no
# internal one is there). Internal headers (overlay_clip.h, the volume
# kernels, the solver set-up, the CLI's config code) stay in the source tree.
# They keep the source layout under include/surfreg/, because they include
# each other as "measure/x.h", "io/x.h".
set(SURFREG_PUBLIC_MEASURE_HEADERS
  convex_hull.h delaunay.h domain.h dz_statistics.h grid_mesh.h
  input_error.h mask_region.h measure_keys.h measures.h mesh.h option_keys.h surface.h tasks.h
  uninitialized_vector.h volume.h)
set(SURFREG_PUBLIC_REGISTRATION_HEADERS
  align.h align_keys.h align_options.h align_result.h holdout.h rigid_motion.h series.h stable_terrain.h)
set(SURFREG_PUBLIC_FACES_HEADERS asymmetry_cohort.h asymmetry_index.h face_frame.h helical_axis.h jaw.h jaw_split.h symmetry.h)
set(SURFREG_PUBLIC_TERRAIN_HEADERS change_budget.h change_uncertainty.h dod_error.h geo_frame.h series_epochs.h
  spatial_budget.h terrain.h
  terrain_keys.h terrain_measure.h terrain_request.h tiled_error.h tiled_measure.h tiled_motion.h tiled_partial.h
  variogram.h)
set(SURFREG_PUBLIC_IO_HEADERS
  mesh_reader.h plot.h polygon_reader.h raster_io.h surface_reader.h surface_writer.h)
list(TRANSFORM SURFREG_PUBLIC_MEASURE_HEADERS PREPEND ${PROJECT_SOURCE_DIR}/measure/)
list(TRANSFORM SURFREG_PUBLIC_REGISTRATION_HEADERS PREPEND ${PROJECT_SOURCE_DIR}/registration/)
list(TRANSFORM SURFREG_PUBLIC_FACES_HEADERS PREPEND ${PROJECT_SOURCE_DIR}/faces/)
list(TRANSFORM SURFREG_PUBLIC_TERRAIN_HEADERS PREPEND ${PROJECT_SOURCE_DIR}/terrain/)
list(TRANSFORM SURFREG_PUBLIC_IO_HEADERS PREPEND ${PROJECT_SOURCE_DIR}/io/)
set(surfreg_include_dir ${CMAKE_INSTALL_INCLUDEDIR}/surfreg)
install(FILES ${SURFREG_PUBLIC_MEASURE_HEADERS} DESTINATION ${surfreg_include_dir}/measure)
install(FILES ${SURFREG_PUBLIC_REGISTRATION_HEADERS} DESTINATION ${surfreg_include_dir}/registration)
install(FILES ${PROJECT_SOURCE_DIR}/registration/volume_cost/cell_kernel.h
        DESTINATION ${surfreg_include_dir}/registration/volume_cost)
install(FILES ${SURFREG_PUBLIC_FACES_HEADERS} DESTINATION ${surfreg_include_dir}/faces)
install(FILES ${SURFREG_PUBLIC_IO_HEADERS} DESTINATION ${surfreg_include_dir}/io)
install(FILES ${SURFREG_PUBLIC_TERRAIN_HEADERS} DESTINATION ${surfreg_include_dir}/terrain)

# Two export sets: the core (measure, registration, faces) and the readers and
# writers (io, whose GDAL calls are in the run-time module below).
set(surfreg_library_destinations ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS surfreg_measure surfreg_registration surfreg_faces EXPORT surfregTargets
        ${surfreg_library_destinations})
install(TARGETS surfreg_io EXPORT surfregIoTargets ${surfreg_library_destinations})
install(TARGETS surfreg_terrain EXPORT surfregTerrainTargets ${surfreg_library_destinations})
install(TARGETS surfreg RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The GDAL module (io/gdal_module.h), loaded by surfreg::io at run time.
if(SURFREG_GDAL)
  install(TARGETS surfreg_gdal LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/surfreg)
endif()

set(surfreg_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/surfreg)
install(EXPORT surfregTargets NAMESPACE surfreg:: DESTINATION ${surfreg_cmake_dir})
install(EXPORT surfregIoTargets NAMESPACE surfreg:: DESTINATION ${surfreg_cmake_dir})
install(EXPORT surfregTerrainTargets NAMESPACE surfreg:: DESTINATION ${surfreg_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/surfregConfig.cmake.in
  ${PROJECT_BINARY_DIR}/surfregConfig.cmake INSTALL_DESTINATION ${surfreg_cmake_dir})
# 0.x: a minor release may change the API, so only the same minor version matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/surfregConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/surfregConfig.cmake
              ${PROJECT_BINARY_DIR}/surfregConfigVersion.cmake
        DESTINATION ${surfreg_cmake_dir})
