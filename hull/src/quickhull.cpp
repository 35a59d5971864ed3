// Quickhull with face merging during construction. The algorithm and its
// invariants are described in quickhull.hpp; this file adds the details of
// the working structure:
//   * half-edges store their origin as an index into the (recentred) input
//     points, so output vertices are input points by construction;
//   * faces carry a plane, centroid and area (Newell's method) and a
//     conflict list: a contiguous range of a shared pool holding each
//     point's coordinates with its index, in the order the points joined
//     (the newest last), so the passes over a face's points read memory in
//     order instead of chasing per-point links. A face's range moves to the
//     pool's end when it grows; the abandoned ranges are reclaimed by
//     moving the live ones down (compact_pool) when the pool would
//     otherwise have to grow with an eighth of it abandoned; an iteration's
//     orphans are read from the removed faces' abandoned ranges in place;
//   * removed faces are marked deleted and stay in place; when the face
//     array has doubled, the live faces and edges move down in order
//     (compact_working), and the end compacts the rest in the same walk
//     that checks the solid (survey).
// Faces are processed in creation order (a cursor over the face array, which
// the moves keep): every face that can ever hold conflict points is created
// after the cursor, so one pass over the array visits them all.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <hedra/hull/assert.hpp>
#include <hedra/hull/quickhull.hpp>
#include <limits>
#include <memory>
#include <utility>

#include "mesh_checks.hpp"
#include "outside_search.hpp"

namespace hedra::hull {

const char* to_string(QuickhullStatus status) {
  switch (status) {
    case QuickhullStatus::ok:
      return "ok";
    case QuickhullStatus::empty_input:
      return "empty_input";
    case QuickhullStatus::non_finite_input:
      return "non_finite_input";
    case QuickhullStatus::out_of_range_input:
      return "out_of_range_input";
    case QuickhullStatus::iteration_limit:
      return "iteration_limit";
    case QuickhullStatus::topology_failure:
      return "topology_failure";
  }
  return "unknown";
}

namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kDblEps = std::numeric_limits<double>::epsilon();

// A span for a message, at the precision that shows why it was rejected.
std::string format_extent(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

enum class Mark : std::uint8_t { alive, visible, deleted };

struct WorkEdge {
  Index origin;  // input point index
  Index twin;
  Index next;
  Index prev;
  Index face;
};

struct WorkFace {
  Vec3 normal;
  double offset;
  Vec3 centroid;
  double area;
  Index edge;
  Index begin;  // conflict list: pool[begin, begin + count), the newest last
  Index count;
  Mark mark;

  double distance(const Vec3& p) const { return normal.dot(p) - offset; }
};

// A conflict point: its (recentred) coordinates and its input index.
struct Conflict {
  Vec3 p;
  Index point;
};

// An allocator whose resize leaves new elements default-initialised
// (uninitialised for these plain structs) instead of zeroing them: for the
// pool, the faces and the edges, whose new slots are all written before
// they are read (make_room's callers, build_cone).
template <class T>
struct UninitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitAllocator<U>;
  };
  UninitAllocator() = default;
  template <class U>
  UninitAllocator(const UninitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// The polygon [a, b, c] is counter-clockwise seen from the side its normal
// points to.
Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a); }

}  // namespace

struct QuickhullBuilder::Impl {
  // Working state, kept between builds to avoid reallocation.
  std::vector<Vec3> pts;                                  // recentred input
  std::vector<Index> vertex_of;                           // per point: its output vertex (set by survey)
  std::vector<Conflict, UninitAllocator<Conflict>> pool;  // the faces' conflict ranges, and abandoned ones
  std::size_t pool_live = 0;                              // entries of the pool in live ranges
  std::vector<Index> assign_face;                         // note()d face per item
  std::vector<Index> pending;                             // per face: points about to join (place_noted), else 0
  std::size_t bulk_need = 0;                              // pool entries the noted points need, their faces' included
  // (start, face) of every range placed since the last compact_pool, in
  // pool order (ranges are only ever placed at the pool's end); stale when
  // the face has moved on. compact_pool walks it instead of sorting.
  std::vector<std::pair<Index, Index>> ranges;
  std::vector<WorkEdge, UninitAllocator<WorkEdge>> edges;
  std::vector<WorkFace, UninitAllocator<WorkFace>> faces;
  std::vector<Index> horizon;
  std::vector<Index> visible;
  std::vector<Index> new_faces;
  // An iteration's orphans, in the order they are handed out: the visible
  // faces' points, read in place from their abandoned pool ranges (each
  // span newest first), then `orphans`, copies of the points merges left
  // without a face. The abandoned ranges stay intact until compact_pool,
  // which place_orphans runs only after copying them out.
  struct Span {
    Index begin, count;
  };
  std::vector<Span> orphan_spans;
  std::size_t span_orphans = 0;  // points in orphan_spans
  std::vector<Conflict> orphans;
  std::vector<Conflict> orphan_copy;
  std::vector<Index> discarded;
  std::vector<Index> ring;            // a face's vertices, for plane fitting
  std::vector<std::uint8_t> flagged;  // merge_new_faces: per new face, concave seen from the smaller side
  bool collapsed = false;             // a merge found the solid flattened (see absorb)
  struct ConePlane {
    Vec3 normal;
    double offset;
    Index face;
  };
  std::vector<ConePlane> cone;       // the live new faces' planes, packed
  Index extreme[6] = {};             // points of least and greatest x, y, z
  bool merged = false;               // this iteration merged faces (edits beyond the cone)
  Vec3 world_centre = Vec3::Zero();  // the recentring offset of this build
  std::vector<Index> point_stamp;    // per point, for horizon checks and compaction
  Index stamp = 0;
  struct Frame {
    Index cur, stop;
    bool started;
  };
  std::vector<Frame> stack;
  double eps = 0;
  std::size_t compacted_size = 0;                   // the face count after the last compact_working
  std::vector<Index> face_renumber, edge_renumber;  // compact_working's maps

  // ---- face helpers -----------------------------------------------------
  void update_face(Index f) {
    WorkFace& face = faces[f];
    const Index e0 = face.edge, e1 = edges[e0].next, e2 = edges[e1].next;
    if (edges[e2].next == e0) {  // a triangle, the common case: no gathering
      const Index v[3] = {edges[e0].origin, edges[e1].origin, edges[e2].origin};
      face.centroid = (pts[v[0]] + pts[v[1]] + pts[v[2]]) / 3.0;
      const Plane plane = polygon_plane(
          3, [&](std::size_t i) -> const Vec3& { return pts[v[i]]; }, &face.area);
      face.normal = plane.normal;
      face.offset = plane.offset;
      return;
    }
    ring.clear();
    Index e = face.edge;
    do {
      ring.push_back(edges[e].origin);
      e = edges[e].next;
    } while (e != face.edge && ring.size() <= edges.size());
    Vec3 c = Vec3::Zero();
    for (Index p : ring) c += pts[p];
    face.centroid = c / static_cast<double>(ring.size());
    const Plane plane = polygon_plane(
        ring.size(), [&](std::size_t i) -> const Vec3& { return pts[ring[i]]; }, &face.area);
    face.normal = plane.normal;
    face.offset = plane.offset;
  }

  int degree(Index f) const {
    int n = 0;
    Index e = faces[f].edge;
    do {
      ++n;
      e = edges[e].next;
    } while (e != faces[f].edge && n <= static_cast<int>(edges.size()));
    return n;
  }

  Index add_face() {
    faces.push_back(WorkFace{Vec3::Zero(), 0.0, Vec3::Zero(), 0.0, kInvalidIndex, 0, 0, Mark::alive});
    return static_cast<Index>(faces.size() - 1);
  }
  Index add_edge(Index origin, Index face) {
    edges.push_back(WorkEdge{origin, kInvalidIndex, kInvalidIndex, kInvalidIndex, face});
    return static_cast<Index>(edges.size() - 1);
  }
  // A triangle a->b->c; returns its face; twins left for the caller.
  Index add_triangle(Index a, Index b, Index c) {
    const Index f = add_face();
    const Index e0 = add_edge(a, f), e1 = add_edge(b, f), e2 = add_edge(c, f);
    edges[e0].next = e1, edges[e1].next = e2, edges[e2].next = e0;
    edges[e0].prev = e2, edges[e1].prev = e0, edges[e2].prev = e1;
    faces[f].edge = e0;
    return f;
  }
  void link_twins(Index a, Index b) {
    edges[a].twin = b;
    edges[b].twin = a;
  }

  // Gives face f room for `extra` more points after its range: in place when
  // the range ends the pool, otherwise the range moves to the pool's end
  // (its old place is abandoned). Invalidates references into the pool.
  void make_room(Index f, std::size_t extra) {
    WorkFace& face = faces[f];
    const std::size_t end = pool.size();
    if (face.count > 0 && face.begin + face.count == end) {  // listed in `ranges` already
      pool.resize(end + extra);
      return;
    }
    pool.resize(end + face.count + extra);
    std::copy(pool.begin() + face.begin, pool.begin() + face.begin + face.count, pool.begin() + end);
    face.begin = static_cast<Index>(end);
    ranges.emplace_back(face.begin, f);
  }
  // Every caller has checked that c lies more than eps in front of f (the
  // plane may tilt later, when f merges: the eye is rechecked then).
  void push_conflict(Index f, const Conflict& c) {
    HEDRA_ASSERT(faces[f].distance(c.p) > eps);
    make_room(f, 1);
    pool[faces[f].begin + faces[f].count++] = c;
    ++pool_live;
  }
  // Bulk placement, in two steps: note(i, f) for every item i < m in order
  // (f = kInvalidIndex: none), then place_noted(m, item) appends item(i) to
  // the conflict list of its face, in the order of i: what pushing them one
  // by one would give, with each face's range moved at most once.
  void begin_notes(std::size_t m) {
    assign_face.resize(m);
    if (pending.size() < faces.size()) pending.resize(faces.size(), 0);
    bulk_need = 0;
  }
  void note(std::size_t i, Index f) {
    assign_face[i] = f;
    if (f == kInvalidIndex) return;
    if (pending[f]++ == 0) bulk_need += faces[f].count;
    ++bulk_need;
  }
  // Compacting costs the live entries and the ranges placed since the last
  // time (fewer than the entries placed): done when it frees an eighth of
  // the pool, rather than growing it (a reallocation holds the old and the
  // new pool at once).
  bool placing_compacts() const {
    return pool.size() + bulk_need > pool.capacity() && 8 * (pool.size() - pool_live) >= pool.size();
  }
  // Room for the noted points without reallocating while they are placed.
  void reserve_for_notes() {
    const std::size_t need = bulk_need;
    if (pool.size() + need > pool.capacity()) {
      if (placing_compacts()) compact_pool();
      if (pool.size() + need > pool.capacity()) pool.reserve(std::max(pool.size() + need, pool.capacity() / 2 * 3));
    }
  }
  void place_one(Index f, const Conflict& c) {
    if (pending[f] > 0) {
      make_room(f, pending[f]);
      pending[f] = 0;
    }
    HEDRA_ASSERT(faces[f].distance(c.p) > eps);
    pool[faces[f].begin + faces[f].count++] = c;
    ++pool_live;
  }
  template <class Item>
  void place_noted(std::size_t m, Item&& item) {
    reserve_for_notes();
    for (std::size_t i = 0; i < m; ++i) {
      const Index f = assign_face[i];
      if (f != kInvalidIndex) place_one(f, item(i));
    }
  }
  // Moves the live ranges down to the start of the pool, in pool order (each
  // range keeps its order), dropping the abandoned ones. Only between
  // passes: no caller holds a range being read.
  void compact_pool() {
    Index at = 0;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const auto [begin, f] = ranges[i];
      WorkFace& face = faces[f];
      if (face.mark != Mark::alive || face.count == 0 || face.begin != begin) continue;       // stale
      std::copy(pool.begin() + begin, pool.begin() + begin + face.count, pool.begin() + at);  // at <= begin
      face.begin = at;
      ranges[kept++] = {at, f};
      at += face.count;
    }
    HEDRA_ASSERT(at == pool_live);
    ranges.resize(kept);
    pool.resize(at);
  }
  // Moves the conflict points of face `from` to face `to` when they are in
  // front of it, to the orphan list otherwise (newest first, as they are
  // handed out everywhere).
  void move_conflicts(Index from, Index to) {
    const Index begin = faces[from].begin, count = faces[from].count;
    faces[from].count = 0;
    pool_live -= count;
    for (Index k = count; k-- > 0;) {
      const Conflict c = pool[begin + k];  // a copy: pushing may move the pool
      if (to != kInvalidIndex && faces[to].distance(c.p) > eps)
        push_conflict(to, c);
      else
        orphans.push_back(c);
    }
  }

  // ---- merging ------------------------------------------------------------
  // Joins hprev and h so that h follows hprev in their face. When both border
  // the same other face O, the vertex between them has only two faces left
  // and is removed: hprev is kept as the joined edge; if O was a triangle it
  // disappears (returned, to be discarded), otherwise it loses one edge.
  Index connect(Index hprev, Index h) {
    const Index tp = edges[hprev].twin, th = edges[h].twin;
    const Index o = edges[tp].face;
    if (o == edges[hprev].face || faces[o].mark != Mark::alive) {
      collapsed = true;  // the face wraps onto itself: flattened solid
      return kInvalidIndex;
    }
    if (o != edges[th].face) {
      edges[hprev].next = h;
      edges[h].prev = hprev;
      return kInvalidIndex;
    }
    const Index f = edges[hprev].face;
    const Index nh = edges[h].next;
    edges[hprev].next = nh;
    edges[nh].prev = hprev;
    if (faces[f].edge == h) faces[f].edge = hprev;
    if (degree(o) == 3) {
      // O = (w->v = th, v->u = tp, u->w = t3): the edge beyond t3 becomes the
      // twin of the joined u->w.
      const Index outer = edges[edges[tp].next].twin;
      link_twins(hprev, outer);
      faces[o].mark = Mark::deleted;
      return o;
    }
    const Index ntp = edges[tp].next;
    edges[th].next = ntp;
    edges[ntp].prev = th;
    if (faces[o].edge == tp) faces[o].edge = th;
    link_twins(hprev, th);
    update_face(o);
    return kInvalidIndex;
  }

  // Face F = face(adj) absorbs the face across adj, together with every edge
  // the two share in a run around adj.
  void absorb(Index adj) {
    const Index f = edges[adj].face;
    const Index opp = edges[adj].twin;
    const Index g = edges[opp].face;
    if (g == f) {
      collapsed = true;  // an edge with the same face on both sides: flattened solid
      return;
    }
    faces[g].mark = Mark::deleted;
    merged = true;
    discarded.push_back(g);
    Index adj_prev = edges[adj].prev, adj_next = edges[adj].next;
    Index opp_prev = edges[opp].prev, opp_next = edges[opp].next;
    const int deg_f = degree(f), deg_g = degree(g);
    int shared = 1;
    for (; edges[edges[adj_prev].twin].face == g && shared < deg_f; ++shared) {
      adj_prev = edges[adj_prev].prev;
      opp_next = edges[opp_next].next;
    }
    for (; edges[edges[adj_next].twin].face == g && shared < deg_f; ++shared) {
      opp_prev = edges[opp_prev].prev;
      adj_next = edges[adj_next].next;
    }
    if ((deg_f - shared) + (deg_g - shared) < 3) {
      // The two faces share all their edges but two: the solid has
      // flattened into these faces (a slab a few eps thick). Leave the
      // structure as it is; the build reports it and retries.
      faces[g].mark = Mark::alive;
      discarded.pop_back();
      collapsed = true;
      return;
    }
    const Index stop = edges[opp_prev].next;
    {
      Index h = opp_next;
      for (int k = 0; h != stop && k < deg_g; ++k, h = edges[h].next) edges[h].face = f;
      if (h != stop) {  // G's chain does not lead back: a broken structure
        collapsed = true;
        return;
      }
    }
    faces[f].edge = adj_next;
    const Index d1 = connect(opp_prev, adj_next);
    if (d1 != kInvalidIndex) discarded.push_back(d1);
    const Index d2 = connect(adj_prev, opp_next);
    if (d2 != kInvalidIndex) discarded.push_back(d2);
    // Removing redundant vertices can shrink a face below a triangle only
    // when the solid has flattened (as above); abandon this attempt.
    if (degree(f) < 3) {
      collapsed = true;
      return;
    }
    update_face(f);
  }

  enum class MergeRule { nonconvex_wrt_larger, nonconvex };

  // Distance of the centroid of the face across e from the plane of e's face.
  double opposite_distance(Index e) const {
    return faces[edges[e].face].distance(faces[edges[edges[e].twin].face].centroid);
  }

  // Merges face f with the first neighbour it is not clearly convex with;
  // returns true if it merged (the caller repeats until false). With
  // nonconvex_wrt_larger, only the larger face's plane decides, and a face
  // that is concave only seen from the smaller one is flagged for the second
  // pass through `nonconvex`.
  bool merge_once(Index f, MergeRule rule, bool& nonconvex) {
    const Index start = faces[f].edge;
    Index e = start;
    std::size_t guard = 0;
    do {
      const Index g = edges[edges[e].twin].face;
      bool merge = false;
      if (rule == MergeRule::nonconvex) {
        merge = opposite_distance(e) > -eps || opposite_distance(edges[e].twin) > -eps;
      } else if (faces[f].area > faces[g].area) {
        if (opposite_distance(e) > -eps)
          merge = true;
        else if (opposite_distance(edges[e].twin) > -eps)
          nonconvex = true;
      } else {
        if (opposite_distance(edges[e].twin) > -eps)
          merge = true;
        else if (opposite_distance(e) > -eps)
          nonconvex = true;
      }
      if (merge) {
        discarded.clear();
        absorb(e);
        if (collapsed) return false;
        for (Index d : discarded) move_conflicts(d, f);
        return true;
      }
      e = edges[e].next;
    } while (e != start && ++guard <= edges.size());
    return false;
  }

  // Nearly coplanar faces meeting at a vertex (dihedral angles within the
  // tolerance of flat, as on a bumpy, almost flat patch) can leave a merged
  // face whose polygon turns outward at that vertex. Such a vertex lies in a
  // wedge filled by faces coplanar with this one within eps: absorb the face
  // across the edge leading into it, until the polygon is convex.
  bool merge_reflex_once(Index f) {
    const Index start = faces[f].edge;
    Index e = start;
    std::size_t guard = 0;
    do {
      const Index nx = edges[e].next;
      const Vec3& a = pts[edges[e].origin];
      const Vec3& b = pts[edges[nx].origin];
      const Vec3& c = pts[edges[edges[nx].next].origin];
      const Vec3 d = b - a;
      const double dl = d.norm();
      if (dl > 0 && d.cross(faces[f].normal).dot(c - b) > eps * dl) {
        discarded.clear();
        absorb(e);
        if (collapsed) return false;
        for (Index g : discarded) move_conflicts(g, f);
        return true;
      }
      e = nx;
    } while (e != start && ++guard <= edges.size());
    return false;
  }

  void merge_new_faces() {
    const std::size_t cap = faces.size() + 1;
    std::vector<Index>& nf = new_faces;
    flagged.assign(nf.size(), 0);
    for (std::size_t i = 0; i < nf.size() && !collapsed; ++i) {
      if (faces[nf[i]].mark != Mark::alive) continue;
      bool nonconvex = false;
      for (std::size_t k = 0; k < cap; ++k) {
        nonconvex = false;
        if (!merge_once(nf[i], MergeRule::nonconvex_wrt_larger, nonconvex)) break;
      }
      flagged[i] = nonconvex;
    }
    for (std::size_t i = 0; i < nf.size() && !collapsed; ++i) {
      if (!flagged[i] || faces[nf[i]].mark != Mark::alive) continue;
      bool unused = false;
      for (std::size_t k = 0; k < cap; ++k)
        if (!merge_once(nf[i], MergeRule::nonconvex, unused)) break;
    }
    // A fresh triangle cannot turn outward: only merged faces need this.
    for (std::size_t i = 0; i < nf.size() && !collapsed && merged; ++i) {
      if (faces[nf[i]].mark != Mark::alive) continue;
      for (std::size_t k = 0; k < cap; ++k) {
        if (!merge_reflex_once(nf[i])) break;
        bool unused = false;  // the grown face may now be concave with a neighbour
        for (std::size_t j = 0; j < cap; ++j)
          if (!merge_once(nf[i], MergeRule::nonconvex, unused)) break;
      }
    }
  }

  // ---- one iteration ------------------------------------------------------
  // Collects the faces visible from point `eye` starting at face f0 (which
  // sees it) and the horizon: half-edges of visible faces whose twins are in
  // faces that do not see it, in counter-clockwise order around the region.
  void find_horizon(Index eye, Index f0) {
    horizon.clear();
    visible.clear();
    stack.clear();
    faces[f0].mark = Mark::visible;
    visible.push_back(f0);
    stack.push_back({faces[f0].edge, faces[f0].edge, false});
    const Vec3& p = pts[eye];
    std::size_t guard = 0;
    while (!stack.empty() && ++guard <= 4 * edges.size()) {
      Frame& fr = stack.back();
      if (fr.started && fr.cur == fr.stop) {
        stack.pop_back();
        continue;
      }
      const Index e = fr.cur;
      fr.started = true;
      fr.cur = edges[e].next;
      const Index t = edges[e].twin;
      const Index g = edges[t].face;
      if (faces[g].mark == Mark::visible) continue;
      if (faces[g].distance(p) > eps) {
        faces[g].mark = Mark::visible;
        visible.push_back(g);
        stack.push_back({edges[t].next, t, true});
      } else {
        horizon.push_back(e);
      }
    }
  }

  // The horizon must be one simple closed loop.
  bool horizon_is_simple() {
    const std::size_t n = horizon.size();
    if (n < 3) return false;
    ++stamp;
    for (std::size_t i = 0; i < n; ++i) {
      const Index e = horizon[i];
      const Index dest = edges[edges[e].twin].origin;
      if (edges[horizon[(i + 1) % n]].origin != dest) return false;
      if (point_stamp[dest] == stamp) return false;
      point_stamp[dest] = stamp;
    }
    return true;
  }

  // ---- one iteration: cone, merge, orphans --------------------------------
  // Adds point `eye` to the hull whose visible faces and horizon find_horizon
  // collected: removes the visible faces, builds the cone, merges it, and
  // hands the orphaned conflict points to the new faces.
  void add_point(Index eye, Index eye_face, Index eye_at) {
    remove_visible_faces(eye_face, eye_at);
    build_cone(eye);
    merge_new_faces();
    if (collapsed) return;  // the structure is abandoned; see absorb()
    assign_orphans();
  }

  // Marks the visible faces deleted; their conflict points (but the eye,
  // at eye_at in the list of face eye_face) become orphans, left in place.
  void remove_visible_faces(Index eye_face, Index eye_at) {
    orphans.clear();
    orphan_spans.clear();
    span_orphans = 0;
    const auto add_span = [&](Index begin, Index count) {
      if (count == 0) return;
      orphan_spans.push_back({begin, count});
      span_orphans += count;
    };
    for (Index f : visible) {
      WorkFace& face = faces[f];
      face.mark = Mark::deleted;
      if (f == eye_face) {
        add_span(face.begin + eye_at + 1, face.count - eye_at - 1);
        add_span(face.begin, eye_at);
      } else {
        add_span(face.begin, face.count);
      }
      pool_live -= face.count;
      face.count = 0;
    }
  }
  // Calls fn(i, conflict) for every orphan i in order.
  template <class Fn>
  void for_each_orphan(Fn&& fn) const {
    std::size_t i = 0;
    for (const Span& span : orphan_spans)
      for (Index k = span.count; k-- > 0;) fn(i++, pool[span.begin + k]);
    for (const Conflict& c : orphans) fn(i++, c);
  }

  // A cone of triangles (a, b, eye), one per horizon edge a->b, linked to the
  // faces beyond the horizon and to each other around the eye.
  void build_cone(Index eye) {
    new_faces.clear();
    // Triangle i is face f0 + i with edges e0 + 3i (a->b), + 1 (b->eye),
    // + 2 (eye->a); its side edges meet those of triangles i + 1 and i - 1
    // around the horizon. The arrays grow once for the whole cone.
    const Index m = static_cast<Index>(horizon.size());
    const Index f0 = static_cast<Index>(faces.size()), e0 = static_cast<Index>(edges.size());
    // Capacity doubles, as one push at a time would give (resize alone would
    // size it after the current length, up to twice the memory).
    if (f0 + m > faces.capacity()) faces.reserve(std::max<std::size_t>(2 * faces.capacity(), f0 + m));
    if (e0 + 3 * m > edges.capacity()) edges.reserve(std::max<std::size_t>(2 * edges.capacity(), e0 + 3 * m));
    faces.resize(f0 + m);
    edges.resize(e0 + 3 * m);
    for (Index i = 0; i < m; ++i) {
      const Index h = horizon[i], f = f0 + i, base = e0 + 3 * i;
      const Index outer = edges[h].twin;
      const Index before = e0 + 3 * ((i + m - 1) % m), after = e0 + 3 * ((i + 1) % m);
      edges[base] = WorkEdge{edges[h].origin, outer, base + 1, base + 2, f};
      edges[base + 1] = WorkEdge{edges[outer].origin, after + 2, base + 2, base, f};
      edges[base + 2] = WorkEdge{eye, before + 1, base, base + 1, f};
      edges[outer].twin = base;
      WorkFace& face = faces[f];
      face.edge = base;
      face.begin = face.count = 0;
      face.mark = Mark::alive;
      update_face(f);
      new_faces.push_back(f);
    }
#if HEDRA_ASSERTS_ENABLED
    // The horizon is one closed loop, so each side edge meets its twin
    // running the other way: the cone's links agree around the eye.
    for (Index f : new_faces) {
      Index e = faces[f].edge;
      for (int k = 0; k < 3; ++k, e = edges[e].next) {
        HEDRA_ASSERT(edges[edges[e].twin].twin == e);
        HEDRA_ASSERT(edges[edges[e].next].prev == e);
        HEDRA_ASSERT(edges[edges[e].next].origin == edges[edges[e].twin].origin);
      }
    }
#endif
  }

  // Hands each orphan to the new face it is farthest in front of (stopping
  // early when one is clearly in front); the rest are inside. The live new
  // faces' planes are packed together first: this loop is the hot one.
  void assign_orphans() {
    cone.clear();
    for (Index f : new_faces)
      if (faces[f].mark == Mark::alive) cone.push_back({faces[f].normal, faces[f].offset, f});
    const std::size_t m = span_orphans + orphans.size();
    begin_notes(m);
    for_each_orphan([&](std::size_t i, const Conflict& orphan) {
      const Vec3& q = orphan.p;
      Index best = kInvalidIndex;
      double best_distance = eps;
      for (const ConePlane& c : cone) {
        const double d = c.normal.dot(q) - c.offset;
        if (d > best_distance) {
          best_distance = d;
          best = c.face;
          if (d > 1000 * eps) break;
        }
      }
      note(i, best);
    });
    if (placing_compacts()) {
      // Compaction would overwrite the abandoned ranges the orphans are in.
      orphan_copy.clear();
      for_each_orphan([&](std::size_t, const Conflict& c) { orphan_copy.push_back(c); });
      place_noted(m, [&](std::size_t i) -> const Conflict& { return orphan_copy[i]; });
      return;
    }
    reserve_for_notes();  // grows the pool if it must, without compacting
    // Placing then writes past the pool's end only, and never reallocates.
    HEDRA_ASSERT(pool.size() + bulk_need <= pool.capacity());
    for_each_orphan([&](std::size_t i, const Conflict& c) {
      const Index f = assign_face[i];
      if (f != kInvalidIndex) place_one(f, c);
    });
  }

  // ---- degenerate hulls ---------------------------------------------------
  void finish_point(Index i0, const Eigen::Vector3d* input, QuickhullResult& r) {
    r.dimension = 0;
    r.mesh.vertices.push_back({input[i0], kInvalidIndex});
    r.input_index.push_back(i0);
  }
  void finish_segment(Index i0, Index i1, const Eigen::Vector3d* input, QuickhullResult& r) {
    r.dimension = 1;
    r.mesh.vertices.push_back({input[i0], kInvalidIndex});
    r.mesh.vertices.push_back({input[i1], kInvalidIndex});
    r.input_index = {i0, i1};
  }
  void finish_polygon(const Vec3& u, const Vec3& v, std::size_t n, const Eigen::Vector3d* input, QuickhullResult& r) {
    std::vector<Eigen::Vector2d> xy(n);
    for (std::size_t i = 0; i < n; ++i) xy[i] = {pts[i].dot(u), pts[i].dot(v)};
    std::vector<Index> order, ring;
    monotone_chain(xy, order, ring);
    if (ring.size() < 3) return;  // caller treats this as a segment
    r.dimension = 2;
    const Index m = static_cast<Index>(ring.size());
    for (Index i = 0; i < m; ++i) {
      r.mesh.vertices.push_back({input[ring[i]], kInvalidIndex});
      r.input_index.push_back(ring[i]);
    }
    // Face 0 counter-clockwise around u x v, face 1 the same ring reversed.
    std::vector<std::vector<Index>> polys(2);
    for (Index i = 0; i < m; ++i) {
      polys[0].push_back(i);
      polys[1].push_back(m - 1 - i);
    }
    std::vector<Eigen::Vector3d> positions;
    positions.reserve(m);
    for (const auto& vx : r.mesh.vertices) positions.push_back(vx.position);
    HalfEdgeMesh::from_polygons(positions, polys, r.mesh);
  }

  // Andrew's monotone chain; ring = counter-clockwise hull, points within eps
  // of a hull edge dropped.
  void monotone_chain(const std::vector<Eigen::Vector2d>& xy, std::vector<Index>& order, std::vector<Index>& ring) {
    const Index n = static_cast<Index>(xy.size());
    order.resize(n);
    for (Index i = 0; i < n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](Index a, Index b) {
      if (xy[a].x() != xy[b].x()) return xy[a].x() < xy[b].x();
      if (xy[a].y() != xy[b].y()) return xy[a].y() < xy[b].y();
      return a < b;
    });
    // Andrew's chain with the plain sign of the cross product: a convex
    // ring with every extreme point, however close to collinear.
    auto keeps = [&](Index o, Index a, Index p) {
      const Eigen::Vector2d w = xy[p] - xy[o], s = xy[a] - xy[o];
      return w.x() * s.y() - w.y() * s.x() > 0.0;  // a strictly left of o->p
    };
    ring.clear();
    for (Index k = 0; k < n; ++k) {
      while (ring.size() >= 2 && !keeps(ring[ring.size() - 2], ring.back(), order[k])) ring.pop_back();
      if (ring.empty() || xy[ring.back()] != xy[order[k]]) ring.push_back(order[k]);
    }
    const std::size_t lower = ring.size();
    for (Index k = n; k-- > 0;) {
      while (ring.size() > lower && !keeps(ring[ring.size() - 2], ring.back(), order[k])) ring.pop_back();
      if (xy[ring.back()] != xy[order[k]]) ring.push_back(order[k]);
    }
    // The upper chain ends at the first point again.
    if (ring.size() > 1 && ring.back() == ring.front()) ring.pop_back();
    // Then drop, one at a time, every vertex within eps of the chord of its
    // neighbours (near-duplicates and near-collinear runs): the dropped point
    // stays within eps of the ring. Deciding collinearity on the finished
    // ring rather than while chaining matters: chaining with an eps test
    // dropped a true corner whose x tied with its neighbour's after a
    // projection basis tilted by 1e-10 rad.
    for (std::size_t pass = 0, removed = 1; removed > 0 && ring.size() > 2 && pass <= n; ++pass) {
      removed = 0;
      for (std::size_t i = 0; i < ring.size() && ring.size() > 2;) {
        const Eigen::Vector2d& o = xy[ring[(i + ring.size() - 1) % ring.size()]];
        const Eigen::Vector2d& a = xy[ring[i]];
        const Eigen::Vector2d& p = xy[ring[(i + 1) % ring.size()]];
        const Eigen::Vector2d w = p - o, s = a - o;
        const double length = w.norm();
        const bool near_chord = std::abs(w.x() * s.y() - w.y() * s.x()) <= eps * length;
        const double along = s.dot(w);
        if ((near_chord && along >= 0.0 && along <= length * length) || s.norm() <= eps || (a - p).norm() <= eps) {
          ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
          ++removed;
        } else {
          ++i;
        }
      }
    }
  }

  // Consistency of the working structure (debugging aid): "" when sound.
  std::string check_structure() const {
    for (Index f = 0; f < faces.size(); ++f) {
      if (faces[f].mark != Mark::alive) continue;
      Index e = faces[f].edge;
      std::size_t n = 0;
      do {
        const WorkEdge& h = edges[e];
        if (h.face != f)
          return "edge " + std::to_string(e) + " of face " + std::to_string(f) + " names face " +
                 std::to_string(h.face);
        if (edges[h.next].prev != e) return "next/prev broken at edge " + std::to_string(e);
        if (edges[h.twin].twin != e) return "twin broken at edge " + std::to_string(e);
        if (faces[edges[h.twin].face].mark != Mark::alive)
          return "twin of edge " + std::to_string(e) + " (face " + std::to_string(f) + ") in dead face " +
                 std::to_string(edges[h.twin].face) + " mark " + std::to_string(int(faces[edges[h.twin].face].mark));
        if (edges[h.next].origin != edges[h.twin].origin) return "origin(next) != dest at edge " + std::to_string(e);
        e = h.next;
        if (++n > edges.size()) return "face " + std::to_string(f) + " cycle does not close";
      } while (e != faces[f].edge);
      if (n < 3) return "face " + std::to_string(f) + " has " + std::to_string(n) + " edges";
    }
    return "";
  }

  // Checks the faces this iteration created or grew: their cycles close,
  // have at least three edges, and link consistently with their neighbours.
  // Cheap (proportional to the iteration's work); a failure means merging met
  // a flattened solid, and the attempt is abandoned.
  bool new_faces_sound(bool check_neighbors) const {
    auto cycle_ok = [&](Index f) {
      Index e = faces[f].edge;
      std::size_t n = 0;
      do {
        const WorkEdge& h = edges[e];
        if (h.face != f || edges[h.next].prev != e || edges[h.twin].twin != e ||
            faces[edges[h.twin].face].mark != Mark::alive || edges[h.next].origin != edges[h.twin].origin ||
            h.origin == edges[h.twin].origin)
          return false;
        e = h.next;
        if (++n > edges.size()) return false;
      } while (e != faces[f].edge);
      return n >= 3;
    };
    for (Index f : new_faces) {
      if (faces[f].mark != Mark::alive) continue;
      if (!cycle_ok(f)) return false;
      if (!check_neighbors) continue;
      // Their neighbours too: merging edits the faces around the cone.
      Index e = faces[f].edge;
      do {
        if (!cycle_ok(edges[edges[e].twin].face)) return false;
        e = edges[e].next;
      } while (e != faces[f].edge);
    }
    return true;
  }

  // Adapter of the working structure's live faces for OutsideSearch.
  struct WorkFaces {
    const Impl* q;
    std::size_t face_count() const { return q->faces.size(); }
    bool live(Index f) const { return q->faces[f].mark == Mark::alive; }
    const Vec3& normal(Index f) const { return q->faces[f].normal; }
    double offset(Index f) const { return q->faces[f].offset; }
    template <class Fn>
    void for_each_neighbor(Index f, Fn&& fn) const {
      Index e = q->faces[f].edge;
      std::size_t guard = 0;
      do {
        fn(q->edges[q->edges[e].twin].face);
        e = q->edges[e].next;
      } while (e != q->faces[f].edge && ++guard <= q->edges.size());
    }
    template <class Fn>
    void for_each_corner_face(Index f, Fn&& fn) const {
      Index e = q->faces[f].edge;
      std::size_t guard = 0;
      do {
        // The faces around origin(e): its outgoing edges, turning by twin.next.
        Index around = e;
        do {
          fn(q->edges[around].face);
          around = q->edges[q->edges[around].twin].next;
        } while (around != e && ++guard <= q->edges.size());
        e = q->edges[e].next;
      } while (e != q->faces[f].edge && ++guard <= q->edges.size());
    }
  };
  detail::OutsideSearch<WorkFaces> outside_search;
  std::vector<Vec3> hull_vertices;  // the current hull's vertices, for the search's map

  // Puts every point that is not a vertex and lies more than 6 eps in front
  // of a face of the current hull on the conflict list of the face it is
  // farthest in front of (see outside_search.hpp); returns how many.
  std::size_t reinsert_outside_points(std::size_t n) {
    ++stamp;
    Vec3 c = Vec3::Zero();
    double count = 0;
    hull_vertices.clear();
    Index largest = kInvalidIndex;
    for (Index f = 0; f < faces.size(); ++f) {
      if (faces[f].mark != Mark::alive) continue;
      c += faces[f].centroid, count += 1;
      if (largest == kInvalidIndex || faces[f].area > faces[largest].area) largest = f;
      Index e = faces[f].edge;
      std::size_t guard = 0;
      do {
        if (point_stamp[edges[e].origin] != stamp) hull_vertices.push_back(pts[edges[e].origin]);
        point_stamp[edges[e].origin] = stamp;
        e = edges[e].next;
      } while (e != faces[f].edge && ++guard <= edges.size());
    }
    if (count == 0) return 0;
    c /= count;
    std::size_t reinserted = 0;
    bool prepared = false;  // on the first point that is not a vertex (a sphere's are all vertices)
    begin_notes(n);
    std::fill(assign_face.begin(), assign_face.end(), kInvalidIndex);
    // The search's cell bounds may call a point within rounding of the
    // surface inside: here only points more than 6 eps out count, so the
    // answer is the same.
    for (Index i = 0; i < n; ++i) {
      if (point_stamp[i] == stamp) continue;  // a vertex
      if (!prepared && !outside_search.prepare(WorkFaces{this}, c,
                                               detail::rounding_map(hull_vertices, c, faces[largest].normal), n, true))
        return 0;
      prepared = true;
      const auto [face, d] = outside_search.farthest_face_in_front(pts[i]);
      // Within 6 eps counts as on the hull: a near-duplicate of a vertex
      // (dropped as an eye when within eps of it) can stand up to 5 eps in
      // front of a face through that vertex (itself within 4 eps of the
      // plane). 6 eps stays inside mesh.tolerance() = 8 eps + rounding.
      if (face == kInvalidIndex || d <= 6 * eps) continue;
      note(i, face);
      ++reinserted;
    }
    if (reinserted > 0) place_noted(n, [&](std::size_t i) { return Conflict{pts[i], static_cast<Index>(i)}; });
    return reinserted;
  }

  // ---- initial simplex ----------------------------------------------------
  struct Simplex {
    Index i0, i1, i2, i3;
    Vec3 normal;  // of the triangle (i0, i1, i2), unit
  };

  // Picks the initial simplex from the extreme points (step 3 of the outline
  // in quickhull.hpp). Returns false after writing the hull into r when the
  // input is degenerate at this tolerance: a point, a segment or a polygon.
  bool find_simplex(const Eigen::Vector3d* input, std::size_t n, double mesh_tolerance, Simplex& s,
                    QuickhullResult& r) {
    Index i0 = extreme[0], i1 = extreme[1];
    double best = -1;
    for (int a = 0; a < 6; ++a)
      for (int b = a + 1; b < 6; ++b) {
        const double d = (pts[extreme[a]] - pts[extreme[b]]).squaredNorm();
        if (d > best) best = d, i0 = extreme[a], i1 = extreme[b];
      }
    // A point when the widest pair is within the output's tolerance, not only
    // within eps: the validator (and any user of mesh.tolerance()) would see
    // a shorter segment as two coincident end points (two points 2 ulps apart
    // at x = 1.5).
    if (std::sqrt(best) <= std::max(eps, mesh_tolerance)) {
      finish_point(0, input, r);
      return false;
    }
    // Segment ends: the extremes along the direction i0 -> i1.
    const Vec3 dir = (pts[i1] - pts[i0]).normalized();
    {
      double dmin = pts[i0].dot(dir), dmax = pts[i1].dot(dir);
      for (Index i = 0; i < n; ++i) {
        const double d = pts[i].dot(dir);
        if (d < dmin) dmin = d, i0 = i;
        if (d > dmax) dmax = d, i1 = i;
      }
    }
    const Vec3 dir2 = (pts[i1] - pts[i0]).normalized();
    Index i2 = i0;
    best = -1;
    for (Index i = 0; i < n; ++i) {
      const double d = (pts[i] - pts[i0]).cross(dir2).squaredNorm();
      if (d > best) best = d, i2 = i;
    }
    if (std::sqrt(best) <= eps) {
      finish_segment(i0, i1, input, r);
      return false;
    }
    const Vec3 normal = triangle_normal(pts[i0], pts[i1], pts[i2]).normalized();
    Index i3 = i0;
    best = -1;
    for (Index i = 0; i < n; ++i) {
      const double d = std::abs(normal.dot(pts[i] - pts[i0]));
      if (d > best) best = d, i3 = i;
    }
    if (best <= eps) {
      const Vec3 u = dir2, v = normal.cross(u);
      finish_polygon(u, v, n, input, r);
      if (r.dimension != 2) finish_segment(i0, i1, input, r);
      return false;
    }
    s = {i0, i1, i2, i3, normal};
    return true;
  }

  // Resets the working structure to the tetrahedron of s, faces wound
  // outward.
  void add_tetrahedron(Simplex s, std::size_t n) {
    edges.clear();
    faces.clear();
    compacted_size = 0;
    collapsed = false;
    vertex_of.resize(n);
    pool.clear();
    pool_live = 0;
    ranges.clear();
    point_stamp.assign(n, 0);
    stamp = 0;
    if (s.normal.dot(pts[s.i3] - pts[s.i0]) > 0) std::swap(s.i1, s.i2);  // base must face away from i3
    const Index f0 = add_triangle(s.i0, s.i1, s.i2);
    const Index f1 = add_triangle(s.i0, s.i3, s.i1);
    const Index f2 = add_triangle(s.i1, s.i3, s.i2);
    const Index f3 = add_triangle(s.i2, s.i3, s.i0);
    auto e = [&](Index f, int k) {
      Index h = faces[f].edge;
      for (int j = 0; j < k; ++j) h = edges[h].next;
      return h;
    };
    // f0: i0->i1, i1->i2, i2->i0; f1: i0->i3, i3->i1, i1->i0;
    // f2: i1->i3, i3->i2, i2->i1; f3: i2->i3, i3->i0, i0->i2.
    link_twins(e(f0, 0), e(f1, 2));
    link_twins(e(f0, 1), e(f2, 2));
    link_twins(e(f0, 2), e(f3, 2));
    link_twins(e(f1, 0), e(f3, 1));
    link_twins(e(f1, 1), e(f2, 0));
    link_twins(e(f2, 1), e(f3, 0));
    for (Index f = 0; f < 4; ++f) update_face(f);
  }

  // Step 4 for the simplex: each point goes to the face it is farthest in
  // front of, if any.
  void assign_initial_conflicts(const Simplex& s, std::size_t n) {
    begin_notes(n);
    for (Index i = 0; i < n; ++i) {
      if (i == s.i0 || i == s.i1 || i == s.i2 || i == s.i3) {
        note(i, kInvalidIndex);
        continue;
      }
      Index best_face = kInvalidIndex;
      double best_distance = eps;
      for (Index f = 0; f < 4; ++f) {
        const double d = faces[f].distance(pts[i]);
        if (d > best_distance) best_distance = d, best_face = f;
      }
      note(i, best_face);
    }
    place_noted(n, [&](std::size_t i) { return Conflict{pts[i], static_cast<Index>(i)}; });
  }

  // ---- main loop ----------------------------------------------------------
  // Drains the conflict lists, then checks every non-vertex point against the
  // final hull: merging tilts planes, so a point dropped as inside (within
  // eps of the faces it was tested against) can end up farther out. The ones
  // outside by more than 6 eps go back to conflict lists for another round; a
  // few rounds settle it, otherwise the attempt fails and the retry uses a
  // larger eps. The cap counts every point added, over all rounds.
  void expand(std::size_t n, const QuickhullOptions& options, QuickhullResult& r) {
    const std::size_t cap = options.max_iterations > 0 ? options.max_iterations : 4 * n + 4;
    constexpr int kRounds = 4;
    for (int round = 0;; ++round) {
      drain_conflicts(cap, r);
      if (collapsed || r.status != QuickhullStatus::ok) break;
      const std::size_t outside = reinsert_outside_points(n);
      if (outside == 0) break;
      if (round + 1 == kRounds) {
        collapsed = true;
        r.error = std::to_string(outside) + " points still outside after " + std::to_string(kRounds) + " rounds";
        break;
      }
    }
  }

  // Step 5 over the faces in creation order until no conflict point is left,
  // the attempt is abandoned (collapsed) or the cap is reached.
  void drain_conflicts(std::size_t cap, QuickhullResult& r) {
    for (Index cursor = 0; cursor < faces.size() && !collapsed;) {
      if (faces[cursor].mark != Mark::alive || faces[cursor].count == 0) {
        ++cursor;
        continue;
      }
      if (faces.size() >= 2 * compacted_size + 4096) cursor = compact_working(cursor);
      if (r.iterations >= cap) {
        r.status = QuickhullStatus::iteration_limit;
        r.error = "iteration cap of " + std::to_string(cap) + " reached";
        break;
      }
      double eye_distance = 0;
      const Index at = find_eye(cursor, eye_distance);
      const Index eye = pool[faces[cursor].begin + at].point;
      ++r.iterations;
      // On the hull already: the face moved in a merge, or a (near-)duplicate
      // of a vertex.
      if (eye_distance <= eps || near_vertex_of(cursor, eye)) {
        remove_conflict(cursor, at);
        continue;
      }
      add_eye(eye, cursor, at);
    }
  }

  // Removed faces and edges stay in the arrays during a build (the cursor
  // walks faces in creation order). When the face array has doubled since
  // the last time, the live faces and edges move down, in order, and every
  // link is renumbered: memory stays within a few times the live hull's, and
  // the walks over faces meet fewer dead ones. Order is kept, so the build
  // makes the same decisions. Returns the cursor's new index. Live edges are
  // the cycles of live faces; if a link of one leads to a dead element, the
  // structure is left as it is (the end checks will tell).
  Index compact_working(Index cursor) {
    compacted_size = faces.size();
    face_renumber.assign(faces.size(), kInvalidIndex);
    edge_renumber.assign(edges.size(), kInvalidIndex);
    Index nf = 0, ne = 0;
    for (Index f = 0; f < faces.size(); ++f) {
      if (faces[f].mark != Mark::alive) continue;
      face_renumber[f] = nf++;
      Index e = faces[f].edge;
      std::size_t guard = 0;
      do {
        edge_renumber[e] = 0;  // live; numbered below, in index order
        e = edges[e].next;
      } while (e != faces[f].edge && ++guard <= edges.size());
    }
    // Numbering and the check that live edges link only to live elements,
    // in one pass (the check reads liveness, which numbering keeps).
    for (Index e = 0; e < edges.size(); ++e) {
      if (edge_renumber[e] == kInvalidIndex) continue;
      edge_renumber[e] = ne++;
      const WorkEdge& w = edges[e];
      if (edge_renumber[w.twin] == kInvalidIndex || edge_renumber[w.next] == kInvalidIndex ||
          edge_renumber[w.prev] == kInvalidIndex || face_renumber[w.face] == kInvalidIndex)
        return cursor;
    }
    // In place: an element's new index is never above its old one.
    for (Index e = 0; e < edges.size(); ++e) {
      if (edge_renumber[e] == kInvalidIndex) continue;
      WorkEdge w = edges[e];
      w.twin = edge_renumber[w.twin], w.next = edge_renumber[w.next], w.prev = edge_renumber[w.prev];
      w.face = face_renumber[w.face];
      edges[edge_renumber[e]] = w;
    }
    for (Index f = 0; f < faces.size(); ++f) {
      if (face_renumber[f] == kInvalidIndex) continue;
      WorkFace face = faces[f];
      face.edge = edge_renumber[face.edge];
      faces[face_renumber[f]] = face;
    }
    // The pool's range list follows the faces (a removed face's ranges are stale).
    std::size_t kept = 0;
    for (const auto& [begin, f] : ranges)
      if (face_renumber[f] != kInvalidIndex) ranges[kept++] = {begin, face_renumber[f]};
    ranges.resize(kept);
    const Index moved = face_renumber[cursor];
    faces.resize(nf);
    edges.resize(ne);
    compacted_size = nf;
    return moved;
  }

  // The place in face f's list of its farthest conflict point (the eye; of
  // equally far ones, the newest), with its distance in front of f. The eye
  // stays listed: adding it removes the face with its list, so only an eye
  // that is not added is taken out (remove_conflict).
  Index find_eye(Index f, double& eye_distance) const {
    const WorkFace& face = faces[f];
    HEDRA_ASSERT(face.count > 0);
    const Conflict* list = pool.data() + face.begin;
    Index at = face.count - 1;
    eye_distance = -std::numeric_limits<double>::infinity();
    for (Index k = face.count; k-- > 0;) {
      const double d = face.distance(list[k].p);
      if (d > eye_distance) eye_distance = d, at = k;
    }
    return at;
  }
  // Takes the point at `at` out of face f's list; the points after it move
  // down one place: the list keeps its order.
  void remove_conflict(Index f, Index at) {
    WorkFace& face = faces[f];
    std::copy(pool.begin() + face.begin + at + 1, pool.begin() + face.begin + face.count,
              pool.begin() + face.begin + at);
    --face.count;
    --pool_live;
  }

  // A (near-)duplicate of a vertex of its face lies just above the faces
  // around that vertex: it is on the hull already.
  bool near_vertex_of(Index f, Index eye) const {
    const WorkFace& face = faces[f];
    bool duplicate = false;
    Index e = face.edge;
    std::size_t guard = 0;
    do {
      duplicate = (pts[edges[e].origin] - pts[eye]).squaredNorm() <= eps * eps;
      e = edges[e].next;
    } while (!duplicate && e != face.edge && ++guard <= edges.size());
    return duplicate;
  }

  // One iteration for the eye seen by face f: horizon, cone, merge, orphans,
  // then the cheap check of what it touched. Sets `collapsed` when the
  // attempt must be abandoned.
  // The eye is at `at` in f's list.
  void add_eye(Index eye, Index f, Index at) {
    find_horizon(eye, f);
    if (!horizon_is_simple()) {
      // Visibility inconsistent within eps (nearly coplanar faces seen
      // edge-on): no cone can be built without breaking the structure or
      // leaving the point out. Give up this attempt; the retry's larger eps
      // merges those faces.
      for (Index g : visible) faces[g].mark = Mark::alive;
      remove_conflict(f, at);
      collapsed = true;
      return;
    }
    merged = false;
    add_point(eye, f, at);
    // Without a merge the cone is sound by construction (a simple horizon,
    // links set pairwise): only merges need the check.
    HEDRA_ASSERT(collapsed || merged || new_faces_sound(false));
    if (!collapsed && merged && !new_faces_sound(true)) collapsed = true;
#ifdef HEDRA_QUICKHULL_DEBUG
    // Debugging aid: the full O(E) check after every iteration, reporting
    // the first iteration that leaves the structure inconsistent.
    const std::string problem = collapsed ? std::string() : check_structure();
    if (!problem.empty()) {
      std::fprintf(stderr, "quickhull: after adding point %u: %s\n", eye, problem.c_str());
      collapsed = true;
    }
#endif
  }

  // ---- end passes ---------------------------------------------------------
  // One walk over the live faces numbers them, their edges and their
  // vertices for compaction (faces and edges in face order, vertices in order
  // of first use: their input indices go to r.input_index, point -> vertex to
  // vertex_of) and, when `check`, looks at what a sound solid needs:
  // every cycle closes with >= 3 edges whose links agree, no edge is a loop
  // (then V - E + F = 2 rules out pinched, non-manifold vertices), every face
  // is planar and every edge convex within 4 eps (the vertices next to it in
  // the neighbouring face are behind the face's plane). Links are checked
  // before the geometry that follows them; after the first broken link only
  // the numbering goes on.
  struct Survey {
    std::size_t alive = 0, half_edges = 0;
    bool links_sound = true, faces_sound = true;
  };
  bool links_sound_at(Index f, Index e) const {
    const WorkEdge& w = edges[e];
    return w.face == f && edges[w.next].prev == e && edges[w.twin].twin == e && w.twin != e &&
           faces[edges[w.twin].face].mark == Mark::alive && edges[w.next].origin == edges[w.twin].origin &&
           w.origin != edges[w.twin].origin;
  }
  bool face_sound_at(const WorkFace& face, Index e, double tol) const {
    if (std::abs(face.distance(pts[edges[e].origin])) > tol) return false;
    const Index t = edges[e].twin;
    return face.distance(pts[edges[edges[edges[t].next].next].origin]) <= tol;
  }
  Survey survey(bool check, std::vector<Index>& face_map, std::vector<Index>& edge_map, QuickhullResult& r) {
    Survey s;
    ++stamp;
    face_map.assign(faces.size(), kInvalidIndex);
    edge_map.assign(edges.size(), kInvalidIndex);
    Index ne = 0;
    for (Index f = 0; f < faces.size(); ++f) {
      if (faces[f].mark != Mark::alive) continue;
      face_map[f] = static_cast<Index>(s.alive++);
      Index e = faces[f].edge;
      std::size_t n = 0, length = 0;
      do {
        ++length;
        if (check && s.links_sound) {
          s.links_sound = links_sound_at(f, e);
          if (s.links_sound && s.faces_sound) s.faces_sound = face_sound_at(faces[f], e, 4 * eps);
        }
        edge_map[e] = ne++;
        const Index p = edges[e].origin;
        if (point_stamp[p] != stamp) {
          point_stamp[p] = stamp;
          vertex_of[p] = static_cast<Index>(r.input_index.size());
          r.input_index.push_back(p);
        }
        e = edges[e].next;
      } while (e != faces[f].edge && ++n <= edges.size());
      s.links_sound = s.links_sound && e == faces[f].edge && length >= 3;
      s.half_edges += length;
    }
    return s;
  }

  // Sets topology_failure unless the finished structure is a sound solid
  // (see survey), in the order: too few faces, broken links (the structure
  // is then abandoned: collapsed), warped faces. Returns false when there is
  // nothing to compact.
  bool check_solid(bool check, const Survey& s, QuickhullResult& r) {
    if (!check) return true;
    const long long euler = static_cast<long long>(r.input_index.size()) - static_cast<long long>(s.half_edges / 2) +
                            static_cast<long long>(s.alive);
    if (s.alive < 4) {
      // A slab only a few eps thick can merge away into nothing: not a solid
      // at this tolerance (the retry's larger eps sees it as flat).
      r.status = QuickhullStatus::topology_failure;
      r.error = "solid collapsed while merging at tolerance " + std::to_string(eps);
    } else if (!s.links_sound || s.half_edges % 2 != 0 || euler != 2) {
      r.status = QuickhullStatus::topology_failure;
      r.error = "inconsistent structure after merging at tolerance " + std::to_string(eps);
      r.input_index.clear();
      collapsed = true;
      return false;
    } else if (!s.faces_sound) {
      r.status = QuickhullStatus::topology_failure;
      r.error = "faces warped beyond the tolerance " + std::to_string(eps);
    }
    return true;
  }

  QuickhullResult build(const Eigen::Vector3d* input, std::size_t n, const QuickhullOptions& options);
  void build_once(const Eigen::Vector3d* input, std::size_t n, const QuickhullOptions& options, const Vec3& centre,
                  const Vec3& max_abs, QuickhullResult& r);
  void compact(const Eigen::Vector3d* input, QuickhullResult& r);
};

QuickhullResult QuickhullBuilder::Impl::build(const Eigen::Vector3d* input, std::size_t n,
                                              const QuickhullOptions& options) {
  QuickhullResult r;
  if (n == 0 || input == nullptr) {
    r.status = QuickhullStatus::empty_input;
    r.error = "no points";
    return r;
  }
  if (n >= static_cast<std::size_t>(kInvalidIndex) / 8) {
    r.status = QuickhullStatus::empty_input;
    r.error = "too many points (" + std::to_string(n) + ")";
    return r;
  }
  // Recentre on the bounding-box centre; derive the tolerance from the extent.
  // One pass checks the points are finite and finds the bounding box and the
  // points extreme along each axis (the initial simplex starts from those;
  // recentring keeps them extreme).
  Vec3 lo = input[0], hi = input[0];
  for (int axis = 0; axis < 3; ++axis) extreme[2 * axis] = extreme[2 * axis + 1] = 0;
  for (Index i = 0; i < n; ++i) {
    const Vec3& p = input[i];
    if (!p.allFinite()) {
      r.status = QuickhullStatus::non_finite_input;
      r.error = "point " + std::to_string(i) + " has a non-finite coordinate";
      return r;
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (p[axis] < lo[axis]) lo[axis] = p[axis], extreme[2 * axis] = i;
      if (p[axis] > hi[axis]) hi[axis] = p[axis], extreme[2 * axis + 1] = i;
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    // hi - lo overflows to infinity for the widest spans: that fails too.
    if (!(hi[axis] - lo[axis] <= max_input_extent)) {
      r.status = QuickhullStatus::out_of_range_input;
      r.error = "points " + std::to_string(extreme[2 * axis]) + " and " + std::to_string(extreme[2 * axis + 1]) +
                " are more than 1e60 apart along " + "xyz"[axis] +
                " (hull computations multiply coordinate differences and would overflow)";
      return r;
    }
  }
  {
    int axis = 0;
    const double widest = (hi - lo).maxCoeff(&axis);
    if (widest > 0.0 && widest < min_input_extent) {
      r.status = QuickhullStatus::out_of_range_input;
      r.error = "the points span only " + format_extent(widest) + " (points " + std::to_string(extreme[2 * axis]) +
                " and " + std::to_string(extreme[2 * axis + 1]) + " along " + "xyz"[axis] +
                ", the widest axis), less than 1e-60: hull computations multiply coordinate differences and would "
                "underflow";
      return r;
    }
  }
  const Vec3 centre = 0.5 * lo + 0.5 * hi;  // not 0.5 (lo + hi), which can overflow
  pts.resize(n);
  for (std::size_t i = 0; i < n; ++i) pts[i] = input[i] - centre;
  const Vec3 max_abs = (hi - centre).cwiseMax(centre - lo);
  // A tolerance the input cannot satisfy (points so close to coplanar that
  // faces come out warped beyond it, as with clusters of near-duplicates) is
  // retried eightfold larger, up to a millionth of the extent, instead of
  // returning a broken hull; result.tolerance says which one held.
  const double extent = max_abs.x() + max_abs.y() + max_abs.z();
  double tolerance = options.tolerance > 0 ? options.tolerance : 3 * kDblEps * extent;
  for (int attempt = 0;; ++attempt) {
    eps = tolerance;
    QuickhullResult attempt_result;
    build_once(input, n, options, centre, max_abs, attempt_result);
    if (attempt_result.status != QuickhullStatus::topology_failure || tolerance * 8 > 1e-6 * extent || attempt >= 16) {
      attempt_result.iterations += r.iterations;
      return attempt_result;
    }
    r.iterations += attempt_result.iterations;
    tolerance *= 8;
  }
}

void QuickhullBuilder::Impl::build_once(const Eigen::Vector3d* input, std::size_t n, const QuickhullOptions& options,
                                        const Vec3& centre, const Vec3& max_abs, QuickhullResult& r) {
  r.tolerance = eps;
  world_centre = centre;
  // Planes are stored in world coordinates: add what representing them there
  // costs (large offsets), and the slack merging leaves (a merged face is
  // planar within a few eps).
  const double world = 3 * kDblEps * (centre.cwiseAbs().sum() + max_abs.sum());
  const double mesh_tolerance = 8 * eps + 4 * world;

  Simplex simplex;
  if (!find_simplex(input, n, mesh_tolerance, simplex, r)) {
    r.mesh.set_tolerance(mesh_tolerance);  // a point, segment or polygon
    return;
  }
  add_tetrahedron(simplex, n);
  assign_initial_conflicts(simplex, n);
  expand(n, options, r);
  if (collapsed) {  // nothing trustworthy to compact; the caller retries
    if (r.status == QuickhullStatus::ok) {
      r.status = QuickhullStatus::topology_failure;
      r.error = "solid collapsed while merging at tolerance " + std::to_string(eps);
    }
    return;
  }
  compact(input, r);
  if (collapsed) return;
  r.mesh.set_tolerance(mesh_tolerance);
  // The output must pass the validator (O(E) form; its link checks were the
  // survey's, on the working structure) at its own tolerance; if rounding in
  // ill-conditioned input defeated the checks above (three
  // near-duplicates 2e-17 apart on a ray gave a sliver whose world-coordinate
  // plane came out wound against its polygon), the caller retries at a
  // larger eps.
  if (r.status == QuickhullStatus::ok && !detail::validate_rings_and_faces(r.mesh, mesh_tolerance).ok()) {
    r.status = QuickhullStatus::topology_failure;
    r.error = "output failed validation at tolerance " + std::to_string(eps);
  }
}

void QuickhullBuilder::Impl::compact(const Eigen::Vector3d* input, QuickhullResult& r) {
  HalfEdgeMesh& m = r.mesh;
  // New face and edge indices, in face order; vertices in order of first use;
  // the checks of a finished build on the way.
  std::vector<Index> face_map, edge_map;
  const bool check = r.status == QuickhullStatus::ok;
  const Survey s = survey(check, face_map, edge_map, r);
  if (!check_solid(check, s, r)) return;
  r.dimension = 3;
  const Index nf = static_cast<Index>(s.alive), ne = static_cast<Index>(s.half_edges);
  m.vertices.resize(r.input_index.size());
  for (Index v = 0; v < r.input_index.size(); ++v) m.vertices[v] = {input[r.input_index[v]], kInvalidIndex};
  m.edges.resize(ne);
  m.faces.resize(nf);
  for (Index e = 0; e < edges.size(); ++e) {
    if (edge_map[e] == kInvalidIndex) continue;
    const WorkEdge& w = edges[e];
    HalfEdge& h = m.edges[edge_map[e]];
    h.origin = vertex_of[w.origin];
    h.twin = edge_map[w.twin];
    h.next = edge_map[w.next];
    h.prev = edge_map[w.prev];
    h.face = face_map[w.face];
    if (h.twin == kInvalidIndex || h.next == kInvalidIndex || h.prev == kInvalidIndex || h.face == kInvalidIndex) {
      r.status = QuickhullStatus::topology_failure;
      r.error = "internal error: a live half-edge links to a removed element";
    }
  }
  // Planes: the working ones (the checks above used them), moved back to
  // world coordinates.
  for (Index f = 0; f < faces.size(); ++f) {
    if (face_map[f] == kInvalidIndex) continue;
    Face& face = m.faces[face_map[f]];
    face.edge = edge_map[faces[f].edge];
    face.plane.normal = faces[f].normal;
    face.plane.offset = faces[f].offset + faces[f].normal.dot(world_centre);
  }
  m.rebuild_vertex_links();
}

QuickhullBuilder::QuickhullBuilder() : impl_(new Impl) {}
QuickhullBuilder::~QuickhullBuilder() = default;
QuickhullBuilder::QuickhullBuilder(QuickhullBuilder&&) noexcept = default;
QuickhullBuilder& QuickhullBuilder::operator=(QuickhullBuilder&&) noexcept = default;

QuickhullResult QuickhullBuilder::build(const Eigen::Vector3d* points, std::size_t count,
                                        const QuickhullOptions& options) {
  return impl_->build(points, count, options);
}

QuickhullResult build_hull(const std::vector<Eigen::Vector3d>& points, const QuickhullOptions& options) {
  return QuickhullBuilder().build(points, options);
}

namespace {
// Adapter of a finished mesh's faces for OutsideSearch.
struct MeshFaces {
  const HalfEdgeMesh* m;
  std::size_t face_count() const { return m->face_count(); }
  bool live(Index) const { return true; }
  const Vec3& normal(Index f) const { return m->plane(f).normal; }
  double offset(Index f) const { return m->plane(f).offset; }
  template <class Fn>
  void for_each_neighbor(Index f, Fn&& fn) const {
    for (Index n : m->face_neighbors(f)) fn(n);
  }
  template <class Fn>
  void for_each_corner_face(Index f, Fn&& fn) const {
    std::size_t guard = 0;
    for (Index e : m->face_edges(f)) {
      Index around = e;
      do {
        fn(m->left_face(around));
        around = m->rotate_cw(around);
      } while (around != e && ++guard <= m->edges.size());
    }
  }
};
}  // namespace

// The largest signed distance of a point to a face plane. For solids the face
// maximising it is found without scanning every face: the ray from the
// centroid c through p leaves the hull through the face maximising
//   g(f) = n_f . (p - c) / (d_f - n_f . c),
// a linear function of the polar dual's vertex n_f / (d_f - n_f . c), so
// hill-climbing over face adjacency finds it (the dual is convex). If p is
// behind that face it is inside; otherwise the faces that see p form a
// connected patch around it, searched for the largest distance.
double max_outside_distance(const HalfEdgeMesh& mesh, const std::vector<Eigen::Vector3d>& points) {
  double worst = 0;
  const int dim = mesh.dimension();
  if (dim <= 1) {
    if (dim < 0) return 0;
    const Vec3 a = mesh.position(0), b = dim == 1 ? mesh.position(1) : a;
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    for (const auto& p : points) {
      const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      worst = std::max(worst, (p - (a + t * ab)).norm());
    }
    return worst;
  }
  if (dim == 2) {
    // Both faces' planes, and the side planes of the polygon's edges.
    const Plane& pl = mesh.plane(0);
    for (const auto& p : points) {
      double d = std::abs(pl.signed_distance(p));
      for (Index e : mesh.face_edges(0)) {
        const Vec3 a = mesh.position(mesh.origin(e));
        const Vec3 edge = mesh.edge_vector(e);
        const Vec3 side = edge.cross(pl.normal).normalized();
        d = std::max(d, side.dot(p - a));
      }
      worst = std::max(worst, d);
    }
    return worst;
  }
  Vec3 c = Vec3::Zero();
  for (const auto& v : mesh.vertices) c += v.position;
  c /= static_cast<double>(mesh.vertex_count());
  std::vector<Vec3> positions;
  positions.reserve(mesh.vertex_count());
  for (const auto& v : mesh.vertices) positions.push_back(v.position);
  Index largest = 0;
  double largest_area = -1;
  for (Index f = 0; f < mesh.face_count(); ++f) {
    Vec3 newell = Vec3::Zero();
    for (Index e : mesh.face_edges(f))
      newell += (mesh.position(mesh.origin(e)) - c).cross(mesh.position(mesh.destination(e)) - c);
    if (newell.norm() > largest_area) largest_area = newell.norm(), largest = f;
  }
  detail::OutsideSearch<MeshFaces> search;
  if (!search.prepare(MeshFaces{&mesh}, c, detail::rounding_map(positions, c, mesh.plane(largest).normal),
                      points.size())) {
    // Not a proper solid around its vertex average: check every plane.
    for (const auto& p : points)
      for (Index f = 0; f < mesh.face_count(); ++f) worst = std::max(worst, mesh.plane(f).signed_distance(p));
    return worst;
  }
  for (const auto& p : points) worst = std::max(worst, search.farthest_face_in_front(p).second);
  return worst;
}

}  // namespace hedra::hull
