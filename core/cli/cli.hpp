// Subcommands of the cdt3d CLI, one file each.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <string>

namespace cdt3d {
namespace cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;  // input or meshing error (message on stderr)
inline constexpr int kExitUsage = 2;  // bad command line

int run_info(int argc, char** argv);      // cmd_info.cpp
int run_delaunay(int argc, char** argv);  // cmd_delaunay.cpp
int run_mesh(int argc, char** argv);      // cmd_mesh.cpp
int run_repair(int argc, char** argv);    // cmd_repair.cpp

// cmd_repair.cpp: the repair report as table lines and as a JSON object.
std::string repair_summary(const RepairReport& r);
std::string repair_json(const RepairReport& r);

// cmd_mesh.cpp: writes a whole file (IoError naming it on failure).
Status write_text(const std::string& name, const std::string& text);

// cli_json.cpp
std::string json_string(const std::string& s);  ///< quoted and escaped
std::string json_number(double v);              ///< %.17g
std::string json_vec3(const Vec3& p);
void print_json_error(const Error& e);  ///< {"ok":false,"error":{...}} on stdout

}  // namespace cli
}  // namespace cdt3d
