#include "io/text_format.hpp"

#include <charconv>
#include <stdexcept>

namespace rbpart {

std::string round_trip(double value) {
  // std::to_chars without a precision gives the shortest round-tripping digits; "general" lays
  // them out as %g does (0.0005 rather than 5e-04).
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general);
  if (result.ec != std::errc()) throw std::logic_error("round_trip: buffer too small");
  return std::string(buffer, result.ptr);
}

std::string printable(const std::string& text) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const unsigned char c : text) {
    if (c >= 0x20 && c != 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

namespace {

using Json = nlohmann::ordered_json;

// Objects this short whose members are all flat are printed on one line.
constexpr std::size_t kInlineWidth = 100;

bool is_scalar_array(const Json& value) {
  if (!value.is_array()) return false;
  for (const Json& element : value)
    if (element.is_structured()) return false;
  return true;
}

std::string dump_scalar(const Json& value) {
  // Replace (rather than throw on) invalid UTF-8: names built in code are not validated.
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::string dump_inline(const Json& value) {
  if (!value.is_structured()) return dump_scalar(value);
  const bool array = value.is_array();
  std::string out(1, array ? '[' : '{');
  bool first = true;
  for (auto it = value.begin(); it != value.end(); ++it) {
    if (!first) out += ", ";
    first = false;
    if (!array) out += dump_scalar(Json(it.key())) + ": ";
    out += dump_inline(*it);
  }
  out += array ? ']' : '}';
  return out;
}

void dump(const Json& value, const std::string& indent, std::string& out) {
  if (!value.is_structured() || value.empty() || is_scalar_array(value)) {
    out += dump_inline(value);
    return;
  }
  if (value.is_object()) {
    bool flat = true;
    for (const Json& member : value) flat = flat && (!member.is_structured() || is_scalar_array(member));
    if (flat) {
      std::string line = dump_inline(value);
      if (indent.size() + line.size() <= kInlineWidth) {
        out += line;
        return;
      }
    }
  }
  const std::string inner = indent + "  ";
  const bool array = value.is_array();
  out += array ? "[\n" : "{\n";
  for (auto it = value.begin(); it != value.end(); ++it) {
    if (it != value.begin()) out += ",\n";
    out += inner;
    if (!array) out += dump_scalar(Json(it.key())) + ": ";
    dump(*it, inner, out);
  }
  out += '\n';
  out += indent;
  out += array ? ']' : '}';
}

}  // namespace

std::string pretty_json(const nlohmann::ordered_json& value) {
  std::string out;
  dump(value, "", out);
  out += '\n';
  return out;
}

}  // namespace rbpart
