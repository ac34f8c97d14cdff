// Subcommands of the cdt3d CLI, one file each.
#pragma once

namespace cdt3d {
namespace cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;  // input or meshing error (message on stderr)
inline constexpr int kExitUsage = 2;  // bad command line

int run_info(int argc, char** argv);      // cmd_info.cpp
int run_delaunay(int argc, char** argv);  // cmd_delaunay.cpp
int run_mesh(int argc, char** argv);      // cmd_mesh.cpp

}  // namespace cli
}  // namespace cdt3d
