// Temporary placeholder while the real implementation is written (same session).
#include <hedra/hull/quickhull.hpp>
namespace hedra::hull {
const char* to_string(QuickhullStatus s) { (void)s; return "topology_failure"; }
struct QuickhullBuilder::Impl {};
QuickhullBuilder::QuickhullBuilder() : impl_(new Impl) {}
QuickhullBuilder::~QuickhullBuilder() = default;
QuickhullBuilder::QuickhullBuilder(QuickhullBuilder&&) noexcept = default;
QuickhullBuilder& QuickhullBuilder::operator=(QuickhullBuilder&&) noexcept = default;
QuickhullResult QuickhullBuilder::build(const Eigen::Vector3d*, std::size_t, const QuickhullOptions&) {
  QuickhullResult r; r.status = QuickhullStatus::topology_failure; r.error = "not yet"; return r; }
QuickhullResult build_hull(const std::vector<Eigen::Vector3d>& p, const QuickhullOptions& o) { return QuickhullBuilder().build(p, o); }
double max_outside_distance(const HalfEdgeMesh&, const std::vector<Eigen::Vector3d>&) { return 0; }
}
