// compute/contour/contour_qef.hpp - sharp-feature vertex placement for dual contouring: surface normals estimated
// at edge crossings from neighbouring rays, and the quadric error function (QEF) minimiser.
#pragma once

#include "compute/contour/contour_sample.hpp"
#include "compute/model/tridexel.hpp"

namespace tridex::compute::contour {

/// Largest depth difference (grid units) between a crossing and the matching interval end on a
/// neighbouring ray for that end to count as the same surface (surface slopes up to 2 against the ray
/// axis; steeper surfaces are seen by the other ray sets' crossings). TriDexel::kDirtyReachCells (4)
/// counts this window: a crossing in [c, c+1] reads ends in [c - 2, c + 3].
inline constexpr double kNormalWindow = 2.0;
static_assert(kNormalWindow + 2.0 <= TriDexel::kDirtyReachCells, "mark_dirty must cover the normals' window");
/// Two one-sided slopes that differ by at most this much are averaged (central difference); beyond it
/// the ray sits at a crease and its crossing gets no normal (choosing one side, e.g. the flatter one,
/// often picks the face across the crease and throws the vertex off), unless one side is exactly flat across
/// the ray axis (crossing_normal: the crossing then lies on that face).
inline constexpr double kCentralSlopeTol = 0.5;
/// A cell component that has both ordinary crossing normals and crease normals (crossing_normal's flat side) takes
/// the crease normals only when its QEF vertex with them lies within this distance (grid units) of every ordinary
/// crossing's tangent plane (TileContourer): a flat face meeting a cut at a rim inside the cell is consistent with
/// the cut's planes there; a flat face that only touches the cell at its corner is not, and its plane would carry
/// the vertex across the cut.
inline constexpr double kCreaseResidual = 0.25;
/// Corner fill (TileContourer): a cell component with at least two ordinary crossing normals whose QEF vertex lies
/// more than kCornerFillReach (grid units) from its crossings' mass point, behind it (on the material side along the
/// sum of its crossing normals: a concave crease), may sit inside a third surface that fills the crease's corner
/// inside the cell without crossing the cell's edges (a third ball between two, a ball on a box face). The ordinary
/// crossing normals of the 6 face-adjacent cells' edges off the shared faces, each making a dot product above
/// kCornerFillCos with every normal of the component (not a sheet's other wall) and with the mass point in front of
/// its tangent plane or at most kCornerFillFront behind it (the plane separates the vertex from the crossings), are
/// then checked: the tangent plane the vertex lies deepest behind, when deeper than kCornerFillDepth (beyond a smooth
/// surface's bend over a cell or two), joins the QEF and the vertex is placed again.
inline constexpr double kCornerFillReach = 0.5;
inline constexpr double kCornerFillDepth = 0.3;
inline constexpr double kCornerFillCos = -0.5;
inline constexpr double kCornerFillFront = 0.1;
/// Borrowed normals (TileContourer): a cell component none of whose crossings has a normal (an air gap narrower than
/// a cell whose crossings each read the other wall beside them, a crease between two balls) takes, for each crossing,
/// the ordinary normal of a crossing on the edges of the 6 face-adjacent cells off the shared faces that points out of
/// the material along the crossing's edge and whose tangent plane passes nearest to the crossing, within kBorrowReach
/// (grid units). Borrowed normals may belong to both walls of a gap, whose planes meet far from the cell: of normals
/// with a dot product below kBorrowSheetCos (an obtuse angle), only the wall with more of them is kept, as in a
/// sheet (kOpposedNormalCos), so the vertex lies on one wall.
inline constexpr double kBorrowReach = 0.25;
inline constexpr double kBorrowSheetCos = 0.0;
/// Wrong normals at a crest (TileContourer): at the crest of a fin or ridge thinner than a cell, a crossing's
/// neighbouring ray on one side reads the other wall and the ray on the far side has no end within the window, so
/// the one-sided slope (crossing_normal's `one_sided`) gives a normal between the two walls. A cell component whose
/// normals all took such a slope, either a single normal or several (none from a crease's flat side) of which one
/// lies beside a crossing without a normal on a parallel edge of the cell (the neighbouring ray the slope read),
/// borrows as above for its crossings without a normal when the normal borrowed for one of its own normals'
/// crossings makes a dot product below kBorrowWrongCos with that crossing's own normal; its own normals are kept.
/// Slopes of 0 (the edge of a face flat across the ray axis, such as a box face or the rim of a cut in one) do not
/// count; with the parallel-edge condition this keeps most rims and box edges out of the 48-edge scan.
inline constexpr double kBorrowWrongCos = 0.7;
/// Two crossing normals of one cell component whose dot product is below this are the facing walls of a sheet
/// thinner than the cell (about 143 degrees apart or more); the vertex then takes the normals of one wall only
/// (TileContourer).
inline constexpr double kOpposedNormalCos = -0.8;
/// fit_normal(): the crossings span a plane when the scatter matrix's second-smallest eigenvalue exceeds
/// kFitPlaneRatio times the smallest and kFitPlaneSpread (grid units squared).
inline constexpr double kFitPlaneRatio = 4.0;
inline constexpr double kFitPlaneSpread = 1e-6;
/// Largest slope taken from one side alone (the other neighbour has no end within the window): a steeper
/// one-sided difference may come from another sheet (a thin fin beside a plate).
inline constexpr double kOneSidedSlopeMax = 1.0;
/// QEF eigenvalues at most this fraction of the largest are treated as zero (the vertex then keeps the
/// mass point's coordinate along that eigenvector), the SVD truncation of Ju, Losasso, Schaefer and Warren
/// 2002. Lower than their 0.1 because the vertex is confined to its cell (qef_vertex), which bounds what a
/// weakly constrained direction can do: two normals keep both directions when they are more than about 25
/// degrees from parallel or antiparallel (eigenvalues 1 +- |cos|), so a sharp ridge or a thin fin between
/// two cuts is placed on its edge rather than at the mass point.
inline constexpr double kQefTruncation = 0.05;
/// Most cyclic Jacobi sweeps of the 3x3 QEF matrix (quadratic convergence: 5 sweeps reach double
/// precision); sweeps stop earlier once the off-diagonal sum is at most kJacobiTolerance times the
/// diagonal sum (before any sweep for axis-aligned normals).
inline constexpr int kJacobiSweeps = 5;
inline constexpr double kJacobiTolerance = 1e-9;

/// Dot product of two vectors (normals, offsets; grid units) summed in the fixed order (x + y) + z that the GPU
/// contourer repeats, so the CPU and GPU vertices agree bit for bit.
inline double normal_dot(const Vec3& a, const Vec3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }

/// Estimates the outward unit surface normal at the crossing at depth `t` (grid units) on the lattice
/// edge from node n along axis a, whose start node has occupancy `start_inside` (true: the crossing is
/// where a ray of set a leaves material, an interval exit; false: an enter).
///
/// Method (a height field along the ray, finite differences): on the four neighbouring rays of set a
/// (u +- 1, v +- 1, u/v as in RaySet) take the interval end of the same kind nearest to t, accepted
/// within kNormalWindow; per direction, slopes of both sides that agree within kCentralSlopeTol are
/// averaged; where they do not (a crease between the rays), a side whose end lies at exactly depth t (slope 0:
/// a flat face across axis a, such as a box face or a flat-end floor, that the crossing lies on) gives slope 0
/// and `*at_crease` is set (when not nullptr), otherwise no normal; one side present is used alone when its
/// slope is at most kOneSidedSlopeMax (a sharp edge: the ray beyond it has no end within the window) and the
/// lattice line of the ray set along that direction, joining the two rays on the material side of both ends (the node below the lower
/// exit, or the node at or above the higher enter) has no interval end strictly between them (else the neighbour's
/// end lies on another face across a gap narrower than a cell: the far wall of an air valley, the far face of a
/// spike; that line lies up to kNormalWindow + 1 nodes from the crossing's edge node along a), except
/// that a trough or ridge one ray wide (the other side's surface lies beyond the window the other way, told by
/// that ray's occupancy at depth t) gets slope 0 when the other direction has a neighbour end at exactly depth t
/// (a ledge of a face flat across axis a, e.g. a flat-end floor between a deeper cut and a shallower floor, whose
/// one side reads the other floor). Normal = sigma (1, -g_u, -g_v) in (a, u, v),
/// sigma = +1 for an exit, -1 for an enter, normalised. Arithmetic in double in a fixed order (the GPU
/// contourer repeats it bit for bit). Returns false (normal, *at_crease and *one_sided untouched) when a direction
/// has no neighbour end or an unresolved crease; on true, *at_crease tells whether a crease side gave the normal and
/// *one_sided whether a direction's slope other than 0 came from one side alone (a sharp edge of a sloped face, or a
/// crest or fin thinner than a cell whose one neighbour end lies on its other face; not a flat face's edge). Either
/// pointer may be nullptr. O(intervals on 6 rays).
bool crossing_normal(const TriDexel& model, int a, const Node& n, bool start_inside, double t, Vec3& normal,
                     bool* at_crease = nullptr, bool* one_sided = nullptr);

/// Stand-in normal for the crossings of a dual-contouring component that have none of their own (creases
/// the height-field estimate cannot resolve, fallbacks): the outward unit normal of the least-squares plane
/// through the component's `count` crossings `points` (grid units; `mass` = their mean), i.e. the
/// eigenvector of the smallest eigenvalue of their scatter matrix (kJacobiSweeps cyclic Jacobi sweeps),
/// oriented so that it points along each crossing's edge axis `axes[i]` towards the edge's outside node
/// (+axis when `exits[i]`, the crossing leaves material going +axis) on balance. So a cell that knows the
/// normal of one face but not of the surface its other crossings lie on is not pulled onto that face's
/// extension. Returns false (normal untouched) for fewer than 3 points, points that do not span a plane
/// (second-smallest eigenvalue at most kFitPlaneRatio times the smallest, or at most kFitPlaneSpread), or a
/// plane parallel to the balance. Deterministic double arithmetic in a fixed order (mirrored by the GPU
/// contourer). O(count).
bool fit_normal(const Vec3& mass, const Vec3* points, const int* axes, const bool* exits, int count, Vec3& normal);

/// Which branches qef_vertex() took for one vertex (for statistics and tests).
struct QefOutcome {
    int normals = 0;         ///< crossings with a normal in the QEF (0: the clamped mass point)
    bool truncated = false;  ///< at least one eigen-direction dropped (the normals span fewer than 3 directions)
    bool rejected = false;   ///< no finite minimiser (NaN normals or points): the clamped mass point instead
    bool clamped = false;    ///< the free minimiser lay outside the cell: the vertex minimises the QEF on the cell's boundary
};

/// Places a dual vertex by minimising the QEF sum_i (n_i . (x - p_i))^2 of the crossings that have a
/// normal (Ju, Losasso, Schaefer, Warren 2002, "Dual Contouring of Hermite Data", SIGGRAPH) over the cell
/// [cell_lo, cell_lo + 1]. `mass`: mean of ALL the component's crossings (grid units); `points`/`normals`:
/// `count` crossings (grid units) and unit normals. Returns the vertex in grid units, inside the cell.
///
/// Method: the free minimiser relative to the mass point by a truncated eigen-decomposition of A = sum n n^T
/// (up to kJacobiSweeps cyclic Jacobi sweeps; eigenvalues at most kQefTruncation times the largest dropped,
/// so directions the normals do not constrain keep the mass point's coordinate). When it lies outside the
/// cell, the active-set idea of bounded-variable least squares (Stark and Parker 1995, "Bounded-Variable
/// Least-Squares: an Algorithm and Applications", Computational Statistics 10): each coordinate outside is fixed on
/// the nearer cell face and the QEF is minimised again over the remaining coordinates (same truncation
/// floor), until the minimiser lies in the cell (at most three re-solves; constraints are only added, so the
/// result is a feasible point of low QEF, not always the exact constrained minimum). So a normal estimated
/// across a nearby cut (a box edge beside a ball cut) or a sharp edge whose free intersection lies beyond
/// the cell moves the vertex along the cell's boundary, never back to the mass point.
/// count == 0 gives the clamped mass point; so do non-finite normals or points (`rejected`).
/// Deterministic double arithmetic in a fixed order (mirrored by the GPU contourer). `outcome`, when given,
/// receives the branches taken (reset first); nullptr: not reported.
Vec3 qef_vertex(const Vec3& mass, const Vec3* points, const Vec3* normals, int count, const Vec3& cell_lo, QefOutcome* outcome = nullptr);

}  // namespace tridex::compute::contour
