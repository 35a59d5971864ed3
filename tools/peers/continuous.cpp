// The table of continuous peer methods (continuous.hpp) and their crash
// isolation: a ToiPeerResult travels through run_isolated as a PeerResult
// (hit in `intersecting`, the fraction in `distance`).
#include "continuous.hpp"

#include <cmath>

#include "adapters.hpp"

namespace hedra::peers {

namespace detail {
namespace {
class UnsupportedSweep final : public PreparedSweep {
 public:
  explicit UnsupportedSweep(std::string why) : why_(std::move(why)) {}
  ToiPeerResult query() override {
    ToiPeerResult r;
    r.status = why_;
    return r;
  }

 private:
  std::string why_;
};
}  // namespace

std::unique_ptr<PreparedSweep> unsupported_sweep(const char* why) { return std::make_unique<UnsupportedSweep>(why); }
}  // namespace detail

const std::vector<ContinuousPeerMethod>& continuous_peer_methods() {
  static const std::vector<ContinuousPeerMethod> methods = {
      {"bullet_f64_gjk_cast", "Bullet 3.24 double btGjkConvexCast (translation)", false,
       detail::prepare_bullet_f64_gjk_cast},
      {"bullet_f64_subsimplex", "Bullet 3.24 double btSubsimplexConvexCast (translation)", false,
       detail::prepare_bullet_f64_subsimplex},
      {"bullet_f64_continuous", "Bullet 3.24 double btContinuousConvexCollision", true,
       detail::prepare_bullet_f64_continuous},
      {"bullet_f32_continuous", "Bullet 3.24 float btContinuousConvexCollision", true,
       detail::prepare_bullet_f32_continuous},
      {"fcl_naive_trans", "FCL 0.7 continuousCollide, translation, naive (10 samples)", false,
       detail::prepare_fcl_naive_trans},
      {"fcl_ca_trans", "FCL 0.7 continuousCollide, translation, conservative advancement", false,
       detail::prepare_fcl_ca_trans},
      {"fcl_ca_linear", "FCL 0.7 continuousCollide, InterpMotion, conservative advancement", true,
       detail::prepare_fcl_ca_linear},
  };
  return methods;
}

const ContinuousPeerMethod* find_continuous_peer_method(const std::string& name) {
  for (const ContinuousPeerMethod& m : continuous_peer_methods())
    if (name == m.name) return &m;
  return nullptr;
}

std::vector<ToiPeerResult> run_isolated_toi(const std::function<ToiPeerResult(std::size_t)>& call, std::size_t count,
                                            const IsolationSettings& settings) {
  const auto wrapped = [&](std::size_t i) {
    const ToiPeerResult t = call(i);
    PeerResult r;
    r.supported = t.supported;
    r.ok = t.ok;
    r.intersecting = t.hit;
    r.has_distance = true;
    r.distance = t.fraction;
    r.status = t.status;
    r.time_ns = t.time_ns;
    return r;
  };
  std::vector<ToiPeerResult> out;
  out.reserve(count);
  for (const PeerResult& r : run_isolated(wrapped, count, settings)) {
    ToiPeerResult t;
    t.supported = r.supported;
    t.ok = r.ok;
    t.hit = r.intersecting;
    t.fraction = r.distance;
    t.status = r.status;
    t.time_ns = r.time_ns;
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace hedra::peers
