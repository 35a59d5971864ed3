// Text inlined into the viewer page, embedded into the binary at build time
// by embed_text.cmake (see CMakeLists.txt): three.js r111 and its
// OrbitControls from Debian's libjs-three (empty views when the package was
// not installed at configure time), and the viewer's own script and style.
#pragma once

#include <string_view>

namespace hedra::tool::view {

std::string_view embedded_three_js();
std::string_view embedded_orbit_controls_js();
std::string_view embedded_viewer_js();
std::string_view embedded_viewer_css();

}  // namespace hedra::tool::view
