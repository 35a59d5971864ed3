// The table of peer methods (peers.hpp) and the "unsupported" stand-in.
#include <cmath>

#include "adapters.hpp"

namespace hedra::peers {

namespace detail {
namespace {
class Unsupported final : public PreparedPair {
 public:
  explicit Unsupported(std::string why) : why_(std::move(why)) {}
  PeerResult query(PeerQuery) override {
    PeerResult r;
    r.distance = NAN;
    r.status = why_;
    return r;
  }

 private:
  std::string why_;
};
}  // namespace

std::unique_ptr<PreparedPair> unsupported(const char* why) { return std::make_unique<Unsupported>(why); }
}  // namespace detail

const std::vector<PeerMethod>& peer_methods() {
  static const std::vector<PeerMethod> methods = {
      {"ccd_gjk", "libccd 2.1 GJK (boolean only)", detail::prepare_ccd_gjk},
      {"ccd_gjk_epa", "libccd 2.1 GJK + EPA", detail::prepare_ccd_gjk_epa},
      {"ccd_mpr", "libccd 2.1 MPR", detail::prepare_ccd_mpr},
      {"fcl_libccd", "FCL 0.7 GST_LIBCCD", detail::prepare_fcl_libccd},
      {"fcl_indep", "FCL 0.7 GST_INDEP", detail::prepare_fcl_indep},
      {"bullet_f32_gjk_epa", "Bullet 3.24 float btGjkPairDetector + EPA", detail::prepare_bullet_f32_gjk_epa},
      {"bullet_f64_gjk_epa", "Bullet 3.24 double btGjkPairDetector + EPA", detail::prepare_bullet_f64_gjk_epa},
      {"bullet_f32_signed", "Bullet 3.24 float btGjkEpaSolver2::SignedDistance", detail::prepare_bullet_f32_signed},
      {"bullet_f64_signed", "Bullet 3.24 double btGjkEpaSolver2::SignedDistance", detail::prepare_bullet_f64_signed},
  };
  return methods;
}

const PeerMethod* find_peer_method(const std::string& name) {
  for (const PeerMethod& m : peer_methods())
    if (name == m.name) return &m;
  return nullptr;
}

}  // namespace hedra::peers
