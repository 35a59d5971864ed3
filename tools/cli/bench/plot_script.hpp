// The plotting script of `hedra bench` (tools/cli/bench/plot_bench.py),
// embedded into the binary at build time by tools/cli/embed_text.cmake.
#pragma once

#include <string_view>

namespace hedra::tool::bench {

std::string_view plot_script();

}  // namespace hedra::tool::bench
