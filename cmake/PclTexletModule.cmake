# pcl_texlet_module(NAME [HEADER_ONLY] [SOURCES src...] [PUBLIC deps...] [PRIVATE deps...])
#
# One module of pcl_texlet (docs/architecture.md): the target pcl_texlet_NAME, also known as
# pcl_texlet::pcl_texlet_NAME, with the headers of include/pcl_texlet/NAME. A module links only
# what it names here; its public dependencies are those its headers include.
function(pcl_texlet_module name)
  cmake_parse_arguments(M "HEADER_ONLY" "" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  set(target pcl_texlet_${name})
  if(M_HEADER_ONLY)
    add_library(${target} INTERFACE)
    set(scope INTERFACE)
  else()
    add_library(${target} SHARED ${M_SOURCES})
    set(scope PUBLIC)
    # $ORIGIN: an installed module finds the modules it links beside it, wherever the prefix.
    set_target_properties(${target} PROPERTIES VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}
      INSTALL_RPATH "$ORIGIN")
    target_link_libraries(${target} PRIVATE ${M_PRIVATE})
    # PCL's imported targets carry VTK, Qt and Boost in their link interface; a module records
    # only the libraries it calls. GCC implies --as-needed, but not under -fsanitize.
    target_link_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:LINKER:--as-needed>)
    target_compile_options(${target} PRIVATE -Wall -Wextra)
    # The kernels give the same bits at every SIMD level and in every module: no FMA contraction;
    # errno is never read, so sqrt in SIMD loops needs no check.
    target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-ffp-contract=off -fno-math-errno>)
    target_compile_options(${target} PRIVATE ${PCL_TEXLET_LIBRARY_COMPILE_OPTIONS})
    if(PCL_TEXLET_SANITIZE OR PCL_TEXLET_FUZZ)
      # An instrumented library needs its users to link the sanitizer runtimes too.
      target_link_options(${target} INTERFACE -fsanitize=address,undefined)
    endif()
  endif()
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${target})
  target_include_directories(${target} ${scope}
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_definitions(${target} ${scope} ${PCL_TEXLET_EIGEN_DEFINITIONS})
  target_link_libraries(${target} ${scope} ${M_PUBLIC})
  add_library(pcl_texlet::${target} ALIAS ${target})
  set_property(GLOBAL APPEND PROPERTY PCL_TEXLET_MODULES ${target})
endfunction()
