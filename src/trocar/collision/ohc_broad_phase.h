#pragma once
/// OHC: the cascaded, hashed spatial-occupancy broad phase (object AABBs → grid cells →
/// empty / solo / potential-colliding cells → candidate pairs). See docs/collision.md.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/collision/broad_phase.h"

namespace trocar {

namespace ohc_detail {
struct OpenedArrays;  // ohc_kernels.h
}  // namespace ohc_detail

/// OHC tuning. The defaults are what the simulator uses.
struct OhcSettings {
  /// Grid cell edge (metres); 0 = automatic: auto_cell_factor × the root-mean-square edge
  /// length of the primitives hashed this frame (those in the objects' box overlaps; RMS needs
  /// one square root per frame, a mean three per primitive).
  Real cell_size = 0;
  /// Multiplier of the RMS edge length for the automatic cell size (dimensionless). 2 rather
  /// than 1: with a tool finer than the tissue (a jaw's 1 mm triangles against 2.5 mm ones),
  /// cells of one mean edge put each clipped box in ~5 cells, and hashing those entries cost
  /// more than the longer per-cell pair lists of larger cells (bench_collision scene a, with
  /// the mean edge, instructions per frame: factor 1 912K, 1.5 838K, 2 800K, 3 793K; scene b
  /// 1.21M, 1.17M, 1.17M, 1.16M; with the RMS edge 1.5, 1.75, 2 gave 781K, 779K, 766K).
  Real auto_cell_factor = 2.0;
  /// Object-level cascade: hash only the primitives whose box touches the overlap of their
  /// object's box with a partner's box. false hashes every primitive of every object that
  /// overlaps a partner (for tests and measurements of what the cascade saves).
  bool cascade = true;
  /// Cluster-level cascade (only with `cascade`): the pairs (cluster of one object, cluster of
  /// a partner) whose margin-grown boxes overlap are found by a sweep on x; only clusters in
  /// such a pair are opened, and of those only the triangles touching the bounding box of their
  /// cluster's overlaps with its partner clusters are hashed, clipped to it. false stops at the
  /// object level (for tests and measurements of what this level saves).
  bool cluster_cascade = true;
  /// Upper bound on (primitive, cell) entries per hashed primitive, on average: when a frame
  /// would need more (a few huge triangles among tiny ones), the cell size is doubled until it
  /// fits. Keeps memory and time O(primitives) whatever the size mix (dimensionless).
  Real max_cells_per_primitive = 64;
  /// Cluster-pair path (only with both cascade levels): when the cluster sweep completed and
  /// Σ over the overlapping cluster pairs of (opened triangles of one) × (of the other) is at most
  /// this × the opened triangles + 1,024, each cluster pair's triangle boxes are tested against
  /// each other directly (eight or four at a time), then the hits' extents along six more
  /// directions, and the cell hash is skipped: a triangle pair lies in exactly one cluster pair,
  /// so nothing needs deduplicating. The candidates are a subset of the hash's (the extents test
  /// drops about half of the box hits). 0: always hash (for tests and measurements); infinity:
  /// always this path when the sweep completed.
  Real max_pair_tests_per_primitive = 128;
  /// Use the AVX2 kernels (cluster refit, box tests of a cell's pairs) where the CPU has them
  /// and TROCAR_SIMD is not "off". false: the portable code (for tests and comparisons); the
  /// pairs are the same either way.
  bool simd = true;
};

/// What one find_pairs() call did (all counts for that frame only).
struct OhcStats {
  std::uint32_t objects_overlapping = 0;  ///< tested object pairs whose boxes overlap
  std::uint32_t cluster_pairs = 0;        ///< overlapping (cluster, partner cluster) pairs
  std::uint32_t clusters_opened = 0;      ///< clusters whose triangles were tested
  std::uint32_t primitives_hashed = 0;    ///< triangles that passed the cascade
  std::uint64_t entries = 0;              ///< (primitive, cell) entries in the hash table
  std::uint32_t table_size = 0;           ///< hash table slots (power of two, ≥ 2·entries)
  /// Cells of the grid block spanned by the hashed boxes that no primitive touches.
  std::uint64_t empty_cells = 0;
  std::uint64_t cells_touched = 0;        ///< distinct cells holding at least one primitive
  std::uint64_t solo_cells = 0;           ///< touched cells whose primitives are of one object
  std::uint64_t potential_cells = 0;      ///< touched cells with primitives of > 1 object
  std::uint64_t candidate_pairs = 0;      ///< pairs returned (after the box test and dedup)
  /// The candidates came from the cluster pairs' direct box tests (no cell hash: the entries,
  /// table and cell counts are 0).
  bool cluster_pair_path = false;
  Real cell_size = 0;                     ///< cell edge used this frame (metres)
};

/// The cascaded spatial-hash broad phase.
///
/// Per frame, O(vertices + triangles of the overlapping objects + hashed entries):
///  1. object boxes (from the group boxes of step 2); tested pairs (roles, not the same object) whose boxes overlap;
///  2. per object, the region of interest = bounding box of its overlaps with its partners;
///     the triangles are grouped once (when an object is first seen) into clusters of
///     kClusterTriangles triangles, consecutive in Morton order of their centroids, each with
///     the list of its vertices, and every kGroupClusters clusters into a group with the merged
///     list; every frame one pass over the group lists gives the group boxes (their union is
///     the object box of step 1, so positions are read about once), cluster boxes are refitted
///     only in the groups near an overlap, only clusters touching the region (and, by default,
///     a partner's cluster) have their triangles' boxes built, and triangles touching the
///     region are kept with their boxes clipped to it. Then, by default, the cluster-pair path
///     (see OhcSettings::max_pair_tests_per_primitive) instead of steps 3–5;
///  3. cells of edge h on a lattice anchored at the world origin; each hashed box is entered in
///     every cell it touches; cell (x, y, z) goes to slot
///     h(x,y,z) = (x·73856093 ⊕ y·19349663 ⊕ z·83492791) mod n (Teschner et al. 2003,
///     n a power of two, the upper half folded into the lower before masking);
///  4. a counting sort puts each slot's entries together (flat arrays, no lists); a slot's
///     entries are sorted by cell, so hash collisions separate again; each cell is solo or
///     potential-colliding, and only potential-colliding cells emit pairs;
///  5. a pair (a, b) of different objects is emitted only from the cell that contains the
///     minimum corner of the overlap of the two (clipped) boxes — the one cell both are sure to
///     share — so each pair is emitted once without a global set.
/// Buffers grow only when a frame needs more; after that no allocation.
class OhcBroadPhase final : public BroadPhase {
 public:
  /// Triangles per cluster of the cascade's middle level (the last cluster may hold fewer).
  static constexpr std::uint32_t kClusterTriangles = 32;
  /// Clusters per group, the level above clusters that the cluster sweep tests first (the
  /// group boxes come out of the refit at no extra pass).
  static constexpr std::uint32_t kGroupClusters = 32;

  /// Default settings (automatic cell size, cascade on).
  OhcBroadPhase() = default;
  /// Given settings.
  explicit OhcBroadPhase(const OhcSettings& settings) : settings_(settings) {}

  void find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) override;
  BroadPhaseKind kind() const override { return BroadPhaseKind::kOhc; }
  /// Keeps the object's triangle order (its clusters' Morton order) for the cut's new triangles:
  /// the old order without the removed ones, renumbered. The next rebuild of its clusters takes
  /// it instead of sorting the centroids again (a cut moves nothing: the order is as good).
  void remap_object(std::size_t object, std::span<const std::uint32_t> triangle_origin) override;

  const OhcSettings& settings() const { return settings_; }          ///< current settings
  void set_settings(const OhcSettings& settings) { settings_ = settings; }  ///< for the next frame
  const OhcStats& stats() const { return stats_; }                    ///< the last frame's counts

  /// The hash of cell (x, y, z) before the modulo (Teschner et al. 2003 with the fold).
  static std::uint32_t cell_hash(std::int32_t x, std::int32_t y, std::int32_t z) {
    const std::uint32_t h = (static_cast<std::uint32_t>(x) * 73856093u) ^
                            (static_cast<std::uint32_t>(y) * 19349663u) ^
                            (static_cast<std::uint32_t>(z) * 83492791u);
    return h ^ (h >> 16);
  }

 private:
  /// A triangle that passed the cascade: its clipped box and its cell range.
  struct Primitive {
    Vec3 min;                  ///< clipped box, lower corner
    Vec3 max;                  ///< clipped box, upper corner
    std::int32_t lo[3] = {0, 0, 0};  ///< first cell per axis
    std::int32_t hi[3] = {0, 0, 0};  ///< last cell per axis
    std::uint32_t object;      ///< object index
    std::uint32_t triangle;    ///< triangle index in that object
  };
  static_assert(offsetof(Primitive, max) == offsetof(Primitive, min) + 3 * sizeof(Real) &&
                    offsetof(Primitive, hi) == offsetof(Primitive, lo) + 3 * sizeof(std::int32_t),
                "cell_range() reads min, max and writes lo, hi as six consecutive values each");
  /// One (primitive, cell) entry of the table.
  struct Entry {
    std::int32_t x, y, z;      ///< cell
    std::uint32_t primitive;   ///< index into primitives_
  };

  /// One object's cached clusters (rebuilt when the object's identity changes).
  struct ObjectClusters {
    const Triangle* triangles = nullptr;      ///< identity: triangle span data
    std::size_t triangle_count = 0;           ///< identity: triangle span size
    std::size_t vertex_count = 0;             ///< identity: vertex count
    std::vector<std::uint32_t> order;         ///< triangle ids, cluster after cluster
    /// The order to take at the next build instead of the Morton sort (remap_object; empty: none).
    std::vector<std::uint32_t> next_order;
    std::vector<Triangle> ordered;            ///< the triangles' vertex ids in that order
    std::vector<std::uint32_t> vertex_start;  ///< per cluster, first entry in vertices (+ end)
    /// Each cluster's distinct vertices, ascending, as offsets in doubles into the positions
    /// (3 × vertex id; meshes have far fewer than 2³²/3 vertices).
    std::vector<std::uint32_t> vertices;
    std::vector<Aabb> boxes;                  ///< per cluster: box of its vertices (see refitted)
    /// Per kGroupClusters clusters: the distinct vertices of their clusters, as `vertices`
    /// (group_start: per group, first entry in group_vertices, + end). The refit reads these
    /// lists every frame (each vertex about once) and the clusters' lists only of the groups the
    /// cluster sweep meets.
    std::vector<std::uint32_t> group_start;
    std::vector<std::uint32_t> group_vertices;
    std::vector<Aabb> groups;                 ///< per group: box of its vertices this frame
    std::vector<std::uint8_t> refitted;       ///< per group: its clusters' boxes are this frame's
    /// Per cluster, this frame: bounding box of its (grown) box's overlaps with the (grown)
    /// boxes of its partners' clusters (empty: not opened). Used by the cluster cascade only.
    std::vector<Aabb> regions;
    /// The clusters whose region is not empty this frame, each once (capacity: all clusters).
    std::vector<std::uint32_t> touched;
    /// Per touched cluster, this frame: its opened triangles ([first, first + count) of the
    /// opened_ arrays).
    std::vector<std::uint32_t> prim_first;
    std::vector<std::uint32_t> prim_count;
  };
  /// Two overlapping clusters of a tested object pair (i < j), found by the sweep.
  struct ClusterPair {
    Aabb both;                 ///< overlap of the two grown cluster boxes
    std::uint32_t i, cluster_i;
    std::uint32_t j, cluster_j;
  };
  /// A cluster in the cluster-vs-cluster sweep: its grown box and where it comes from.
  struct SweepItem {
    Aabb box;                  ///< cluster box grown by its object's triangle margin bound
    std::uint32_t side;        ///< 0: first object of the pair, 1: second
    std::uint32_t cluster;     ///< cluster index in its object
  };

  static void build_clusters(ObjectClusters& c, const CollisionObject& object);
  /// build_clusters' parts: the Morton order of the centroids (order, ordered), then each
  /// cluster's and group's vertex lists and the per-cluster arrays.
  static void morton_order(ObjectClusters& c, const CollisionObject& object);
  static void build_cluster_lists(ObjectClusters& c, const CollisionObject& object);
  /// The group boxes (all clusters' too when `all_clusters`); returns the object box.
  static Aabb refit_groups(ObjectClusters& c, const CollisionObject& object, bool simd, bool all_clusters);
  /// The boxes of group g's clusters, once per frame.
  static void refit_group_clusters(ObjectClusters& c, const CollisionObject& object, std::size_t g, bool simd);
  void cluster_cascade(std::span<const CollisionObject> objects, std::uint32_t i, std::uint32_t j);

  // find_pairs' phases, in order.
  /// The cascade's cluster level is on (settings).
  bool by_cluster() const { return settings_.cascade && settings_.cluster_cascade; }
  /// Clusters (re)built where an object changed, group boxes, object boxes and margin bounds;
  /// last frame's cluster regions cleared.
  void refit_objects(std::span<const CollisionObject> objects);
  /// The tested object pairs whose boxes overlap: their flags, the objects' regions and (cluster
  /// level) the overlapping cluster pairs.
  void find_overlapping_objects(std::span<const CollisionObject> objects);
  /// The triangles whose box touches their object's (or cluster's) region, into the opened
  /// arrays; returns how many.
  std::uint32_t open_clusters(std::span<const CollisionObject> objects);
  /// The opened arrays, grown to hold every triangle of the clusters that may open.
  ohc_detail::OpenedArrays reserve_opened(std::span<const CollisionObject> objects);
  /// The cluster pairs are all known and their box tests few enough to skip the cell hash.
  bool cluster_pairs_suffice(std::uint32_t opened) const;
  /// The opened triangles as the hash's primitives; returns their root mean square edge length.
  Real copy_opened_to_primitives(std::span<const CollisionObject> objects, std::uint32_t opened);
  /// The cells' range spanned by the primitives, per axis.
  struct CellBlock {
    std::int32_t lo[3];
    std::int32_t hi[3];
  };
  /// Cell size and each primitive's cell range; returns the (primitive, cell) entry count.
  std::uint64_t assign_cells(std::size_t object_count, Real rms_edge, CellBlock& block);
  /// The entries sorted by hash slot (counting sort into entries_, slot_start_); returns the mask.
  std::uint32_t sort_entries_by_slot(std::uint64_t entry_count);
  /// Per slot, the cells with primitives of more than one object, and their candidate pairs.
  void emit_slot_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out,
                       std::uint64_t entry_count, std::uint32_t mask);

  /// The primitive's first and last cells per axis (lo, hi) for cells of edge 1 / inv_h.
  static void cell_range(Primitive& prim, Real inv_h);
  void expand_region(std::uint32_t object, std::uint32_t cluster, const Aabb& box);
  void emit_cell_pairs(std::span<const Entry> cell, std::span<const CollisionObject> objects,
                       std::vector<CandidatePair>& out);
  /// The cluster-pair path: the candidates of every overlapping cluster pair by direct box tests.
  void emit_cluster_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out,
                          std::uint32_t opened);

  OhcSettings settings_;
  OhcStats stats_;
  std::vector<Aabb> boxes_;            // per object
  std::vector<Aabb> regions_;          // per object: bounding box of its overlaps
  std::vector<std::uint8_t> tested_;   // objects² flags: pair tested and boxes overlap
  std::vector<ObjectClusters> clusters_;  // per object
  /// A triangle that passed the cascade this frame: its object and its index there.
  struct OpenedId {
    std::uint32_t object;
    std::uint32_t triangle;
  };
  // The triangles that passed the cascade this frame, in cluster order: their clipped boxes as
  // six arrays of opened_stride_ (min x, y, z, max x, y, z), their extents along six more
  // directions (ohc_kernels.h: six arrays of lower, six of upper ends) and their ids.
  std::vector<Real> opened_boxes_;
  std::vector<OpenedId> opened_ids_;
  std::size_t opened_stride_ = 0;
  std::vector<Primitive> primitives_;  // the cell hash's copy of them, with cell ranges
  std::vector<CandidatePair> pair_scratch_;  // emit_cluster_pairs' AVX-512 output (grows only)
  std::vector<Real> margins_;          // per object: bound on its triangles' box margins
  std::vector<SweepItem> sweep_;       // cluster_cascade scratch (reserved for all clusters)
  std::vector<ClusterPair> cluster_pair_list_;  // this frame's overlapping cluster pairs
  bool sweeps_complete_ = true;        // no sweep hit its step budget this frame
  std::vector<std::uint32_t> slot_start_;  // table_size + 1 (counting sort)
  std::vector<Entry> entries_;
  std::vector<Entry> staged_;              // entries in primitive order, before the counting sort
  std::vector<std::uint32_t> staged_slots_;  // their slots
  std::vector<std::uint8_t> cell_starts_;  // emit_cell_pairs scratch (≥ entries_.size())
  std::vector<std::uint32_t> cell_hits_;   // box test hits scratch (≥ entries or primitives + 8)
  std::vector<std::uint32_t> cell_groups_;  // emit_cell_pairs scratch (≥ entries_.size() + 1)
  std::vector<Real> cell_boxes_;           // emit_cell_pairs scratch: 6 arrays of cell_stride_
  std::size_t cell_stride_ = 0;            // ≥ entries_.size() + 4
};

}  // namespace trocar
