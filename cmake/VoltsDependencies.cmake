# Third-party packages (Debian 12). See scripts/install-deps.sh.
# CGAL ships Find modules that shadow OpenMesh's and Eigen's: find Eigen in CONFIG mode first.
find_package(Eigen3 3.3 REQUIRED CONFIG)
find_package(CGAL REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED)  # core/stage_file.h: type_error::create(id, what, context)
find_package(simdjson 3 REQUIRED CONFIG)  # core/stage_file.cpp: parses the stage files
find_package(VTK 9 REQUIRED COMPONENTS CommonCore CommonDataModel IOXML)
find_package(GTest)

# TetGen has no CMake config.
find_library(TETGEN_LIBRARY NAMES tet)
find_path(TETGEN_INCLUDE_DIR NAMES tetgen.h)

# NLopt (Debian libnlopt-cxx-dev): nlopt.hpp is a header-only C++ wrapper of libnlopt.
find_library(NLOPT_LIBRARY NAMES nlopt)
find_path(NLOPT_INCLUDE_DIR NAMES nlopt.hpp)
