# SPDX-License-Identifier: GPL-3.0-or-later
# The two target shapes every method uses (included by the top-level CMakeLists.txt).
#
# A method lives in one folder: <method>/core (and sometimes a second algorithm folder such as sources/leaf/blade or
# filters/wilting/solver) holds the plain C++17 algorithm layer (Eigen, CGAL, no VTK headers), <method>/vtk the thin VTK
# classes, their vtk.module and their server-manager XML.

# plantmorph_add_algorithm(<library> [DEPENDS <targets>...] [PRIVATE_DEPENDS <targets>...])
#   One static library from every .cpp of the calling folder, whose headers are included by their bare names.
#   DEPENDS are the PlantMorph libraries (and third-party targets) its headers need; PRIVATE_DEPENDS only its
#   sources. Every algorithm library sees the shared mathematics (PlantMorphCommon) and Eigen.
function(plantmorph_add_algorithm library)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "DEPENDS;PRIVATE_DEPENDS")
  file(GLOB sources CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.cpp")
  add_library(${library} STATIC ${sources})
  target_include_directories(${library} PUBLIC "${CMAKE_CURRENT_SOURCE_DIR}")
  target_link_libraries(${library}
    PUBLIC PlantMorphCommon Eigen3::Eigen ${arg_DEPENDS}
    PRIVATE ${arg_PRIVATE_DEPENDS} plantmorph_warnings)
endfunction()

# plantmorph_add_vtk_module(<module> ALGORITHMS <libraries>...)
#   Called from a method's vtk/CMakeLists.txt (the plugin's module scan adds that folder through its vtk.module):
#   the VTK module of every vtk<Name>.{h,cxx} class in the folder (collected, so a new proxy needs no edit here),
#   linked privately to the method's algorithm libraries and to the VTK layer of common/vtk (module
#   PlantMorph::VTKCommon: RunRequestData, the MPI policies and exchanges, field data, preset warning). PRIVATE_SOURCES and
#   PRIVATE_HEADERS: the folder's helpers that are no VTK class (neither wrapped nor installed as API).
function(plantmorph_add_vtk_module module)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "ALGORITHMS;PRIVATE_SOURCES;PRIVATE_HEADERS")
  file(GLOB headers CONFIGURE_DEPENDS RELATIVE "${CMAKE_CURRENT_SOURCE_DIR}" "${CMAKE_CURRENT_SOURCE_DIR}/vtk*.h")
  set(classes)
  foreach (header IN LISTS headers)
    get_filename_component(class "${header}" NAME_WE)
    list(APPEND classes "${class}")
  endforeach ()
  vtk_module_add_module(${module} CLASSES ${classes} SOURCES ${arg_PRIVATE_SOURCES}
    PRIVATE_HEADERS ${arg_PRIVATE_HEADERS})
  vtk_module_include(${module} PRIVATE "${PROJECT_SOURCE_DIR}/common/vtk")
  vtk_module_link(${module} PRIVATE ${arg_ALGORITHMS} plantmorph_warnings)
  if (NOT module MATCHES "^PlantMorph::(VTKCommon|ServerManager)$")
    vtk_module_link(${module} PRIVATE PlantMorph::VTKCommon)
  endif ()
endfunction()
