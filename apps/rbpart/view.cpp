// rbpart view: replays a recording in the browser (docs/viewer.md). Serves the web viewer and the
// recording on 127.0.0.1 (cpp-httplib, Debian's libcpp-httplib-dev), or writes one self-contained
// HTML file with --html.
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <cstring>

#include "apps/rbpart/commands.hpp"
#include "apps/rbpart/viewer_page.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/recording.hpp"

// Last: through <resolv.h> it defines the macro _res, a parameter name inside Eigen.
#include <httplib.h>

#ifndef RBPART_VIEWER_DIR
#error "RBPART_VIEWER_DIR: the build tree's viewer directory, set by CMakeLists.txt"
#endif

namespace rbpart::cli {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

namespace {

std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    for (int k = 18; k >= 0; k -= 6) out.push_back(digits[(v >> k) & 63]);
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (two ? static_cast<unsigned char>(bytes[i + 1]) << 8 : 0);
    out.push_back(digits[(v >> 18) & 63]);
    out.push_back(digits[(v >> 12) & 63]);
    out.push_back(two ? digits[(v >> 6) & 63] : '=');
    out.push_back('=');
  }
  return out;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out.push_back(c);
    }
  }
  return out;
}

// Percent-encoding of a URL fragment value.
std::string url_encode(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      out.push_back(static_cast<char>(c));
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

void replace_marker(std::string& html, const std::string& marker, const std::string& with) {
  const auto at = html.find(marker);
  if (at == std::string::npos) throw std::runtime_error("the viewer's index.html lacks " + marker);
  html.replace(at, marker.size(), with);
}

struct Options {
  std::string file, html;
  int port = 8765;
};

int run_view(const Options& o) {
  const std::string dir = viewer_dir();
  const std::string bytes = read_file(o.file);
  // A bad file is refused here, not in the browser.
  if (parse_recording(bytes, o.file).frames.empty()) throw InputError(o.file + ": the recording holds no step");
  const std::string name = std::filesystem::path(o.file).filename().string();

  if (!o.html.empty()) {
    const std::string page = self_contained_html(bytes, name);
    write_file_atomically(o.html, page);
    std::printf("wrote %s (%.1f MB): the viewer with %s inside; open it in a browser\n", o.html.c_str(),
                page.size() / 1e6, name.c_str());
    return 0;
  }

  // Files are read per request: a rebuilt viewer or a re-recorded file shows on reload.
  httplib::Server server;
  const auto serve_file = [](const std::string& path, const char* type) {
    return [path, type](const httplib::Request&, httplib::Response& res) {
      std::ifstream in(path, std::ios::binary);
      if (!in) {
        res.status = 404;
        return;
      }
      std::ostringstream content;
      content << in.rdbuf();
      res.set_header("Cache-Control", "no-store");
      res.set_content(content.str(), type);
    };
  };
  server.Get("/", serve_file(dir + "/index.html", "text/html; charset=utf-8"));
  server.Get("/index.html", serve_file(dir + "/index.html", "text/html; charset=utf-8"));
  // Debian's httplib compresses text/* and bare "application/javascript" replies with brotli at its
  // highest quality when the browser accepts it: 15 s for the 600 kB bundle. This type (a valid
  // JavaScript type) is outside its list, so the bundle goes out as is, instantly, on loopback.
  server.Get("/viewer.js", serve_file(dir + "/viewer.js", "application/javascript; charset=utf-8"));
  server.Get("/viewer.css", serve_file(dir + "/viewer.css", "text/css; charset=utf-8"));
  server.Get("/recording.rbrec", serve_file(o.file, "application/octet-stream"));

  // httplib's default sets SO_REUSEPORT, with which a second viewer binds a port the first one
  // holds and the kernel splits the connections between them (issue #26): SO_REUSEADDR alone still
  // allows a restart while the old connections linger in TIME_WAIT, but not two listeners.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // Loopback only: the recording is the user's data, not for the network.
  errno = 0;
  const int port = o.port == 0 ? server.bind_to_any_port("127.0.0.1") : (server.bind_to_port("127.0.0.1", o.port) ? o.port : -1);
  if (port <= 0 && errno == EADDRINUSE)
    throw InputError("--port " + std::to_string(o.port) + ": 127.0.0.1:" + std::to_string(o.port) +
                     " is already in use (another rbpart view?); choose another port");
  if (port <= 0)
    throw InputError("--port " + std::to_string(o.port) + ": cannot listen on 127.0.0.1:" + std::to_string(o.port) +
                     (errno ? std::string(": ") + std::strerror(errno) : std::string()));
  std::printf("rbpart view: http://127.0.0.1:%d/#src=recording.rbrec&name=%s\n", port, url_encode(name).c_str());
  std::printf("serving %s and the viewer from %s; Ctrl-C stops\n", o.file.c_str(), dir.c_str());
  std::fflush(stdout);
  if (!server.listen_after_bind()) throw std::runtime_error("the HTTP server stopped");
  return 0;
}

}  // namespace

std::string viewer_dir() {
  const char* env = std::getenv("RBPART_VIEWER_DIR");
  const std::string dir = env && *env ? env : RBPART_VIEWER_DIR;
  for (const char* file : {"index.html", "viewer.js", "viewer.css"})
    if (!std::filesystem::is_regular_file(dir + "/" + file))
      throw InputError("the web viewer is not built (no " + dir + "/" + file +
                       "): run scripts/build_viewer.sh, or set RBPART_VIEWER_DIR to a built viewer");
  return dir;
}

std::string self_contained_html(const std::string& recording_bytes, const std::string& name) {
  const std::string dir = viewer_dir();
  std::string html = read_file(dir + "/index.html");
  const std::string js = read_file(dir + "/viewer.js");
  const std::string css = read_file(dir + "/viewer.css");
  // Inlined text must not end its element early (esbuild escapes "</script" in the bundle).
  if (js.find("</script") != std::string::npos || css.find("</style") != std::string::npos)
    throw std::runtime_error("the viewer's files cannot be inlined (they contain a closing tag)");
  replace_marker(html, "<link rel=\"stylesheet\" href=\"viewer.css\">", "<style>\n" + css + "</style>");
  // The recording first: base64 holds no markup, so the script marker is found in the page itself.
  replace_marker(html, "<!--rbpart:recording-->",
                 "<script id=\"rbpart-recording\" type=\"application/octet-stream\" data-name=\"" +
                     html_escape(name) + "\">" + base64(recording_bytes) + "</script>");
  replace_marker(html, "<script src=\"viewer.js\"></script>", "<script>\n" + js + "</script>");
  return html;
}

Run add_view(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("view", "Replay a recording (simulate --record) in the web viewer");
  auto o = std::make_shared<Options>();
  cmd->add_option("file", o->file, "Recording (.rbrec)")->required();
  cmd->add_option("--port", o->port, "Port on 127.0.0.1 (0: any free port)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  cmd->add_option("--html", o->html, "Write one self-contained HTML file instead of serving");
  return [o]() { return run_view(*o); };
}

}  // namespace rbpart::cli
