// JSON output shared by the subcommands' --json modes.
#include <cstdio>
#include <string>

#include "cli.hpp"

namespace cdt3d {
namespace cli {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_vec3(const Vec3& p) {
  return "[" + json_number(p.x) + "," + json_number(p.y) + "," + json_number(p.z) + "]";
}

void print_json_error(const Error& e) {
  std::printf(
      "{\"ok\":false,\"error\":{\"code\":%s,\"message\":%s,\"file\":%s,\"line\":%lld,"
      "\"record\":%lld,\"facet\":%lld,\"vertex\":%lld,\"otherFacet\":%lld,\"segment\":%lld}}\n",
      json_string(error_code_name(e.code)).c_str(), json_string(e.message).c_str(),
      json_string(e.file).c_str(), static_cast<long long>(e.line), static_cast<long long>(e.record),
      static_cast<long long>(e.facet), static_cast<long long>(e.vertex),
      static_cast<long long>(e.other_facet), static_cast<long long>(e.segment));
}

}  // namespace cli
}  // namespace cdt3d
