#include "trocar/response/settings.h"

namespace trocar {

const char* response_method_name(ResponseMethod method) {
  switch (method) {
    case ResponseMethod::kObb: return "obb";
    case ResponseMethod::kPrimitive: return "primitive";
    case ResponseMethod::kNormal: return "normal";
    case ResponseMethod::kProject: return "project";
    case ResponseMethod::kSdf: return "sdf";
  }
  return "obb";
}

std::optional<ResponseMethod> parse_response_method(std::string_view name) {
  for (const ResponseMethod m : {ResponseMethod::kObb, ResponseMethod::kPrimitive, ResponseMethod::kNormal,
                                 ResponseMethod::kProject, ResponseMethod::kSdf}) {
    if (name == response_method_name(m)) return m;
  }
  return std::nullopt;
}

}  // namespace trocar
