// One self-contained HTML page for a ViewModel (view_model.hpp): three.js
// (Debian's libjs-three, r111) and its OrbitControls inlined at build time,
// the model as an inline JSON block, the viewer (viewer.js, viewer.css) after
// it. Opening the file needs no network and no server.
//
// The page's contract for tests: after its first render it sets
// window.hedraViewReady = true and the attribute data-hedra-ready="true" on
// <html>; every JavaScript error (uncaught exceptions, rejected promises,
// console.error) is appended to window.hedraViewErrors and to the text of
// <pre id="hedra-error-log">, and data-hedra-errors on <html> holds their
// count. `#query=N` or `#face=N` in the URL selects query N or hull face N
// on load.
//
// Safety: names and titles are data, never markup: the JSON block escapes
// every '<' (so "</script>" in a body name cannot end it), and the viewer
// inserts text with textContent only.
#pragma once

#include <string>

#include "cli/view/view_model.hpp"

namespace hedra::tool::view {

// True when three.js was found at build time; otherwise render_view_html
// returns an empty string and three_js_missing_message() says how to fix it.
bool three_js_available();
const char* three_js_missing_message();

std::string render_view_html(const ViewModel& model);

}  // namespace hedra::tool::view
