#pragma once
// The web viewer's static files as `rbpart view` and `rbpart snapshot` use them (docs/viewer.md).
#include <string>

namespace rbpart::cli {

// The built viewer (index.html, viewer.js, viewer.css): $RBPART_VIEWER_DIR if set, else the build
// tree's viewer/ (compile-time RBPART_VIEWER_DIR). Throws InputError saying how to build it.
std::string viewer_dir();

// One HTML file holding the viewer (script and style inlined) and the recording's bytes (base64),
// which opens offline from anywhere. `name` is shown as the recording's name.
std::string self_contained_html(const std::string& recording_bytes, const std::string& name);

// A whole file's bytes; InputError "PATH: cannot read" if it cannot be opened.
std::string read_file(const std::string& path);

}  // namespace rbpart::cli
