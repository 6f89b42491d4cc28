// A billiard table as data, exact: closed loops of straight segments, circular arcs and whole ellipses (the outer
// boundary and any scatterers inside it), each loop with its own arc-length coordinate s in [0, 1) from a stated
// origin. Every value is an ExactReal, so each tier rounds it once (Table<R>, geometry/table.hpp). The standard tables
// are short constructors (stadium, circle, ellipse, mushroom, Sinai, annulus, lemon, Lorentz triangle, polygon);
// docs/tables.md draws each and docs/model.md ("Tables") states the conventions: every loop runs with the table on its
// right (the outer boundary clockwise, a scatterer anticlockwise).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "geometry/table_piece.hpp"
#include "numeric/exact.hpp"

namespace rotleak {

/// One piece of a loop, exact. A segment runs from a to b. An arc of the circle (c, rho) runs from a to b,
/// clockwise or not; a whole circle has a == b and full set. An ellipse is whole: centre c, semi-axes ea along x and
/// eb along y, from its top (cx, cy + eb) round to it (a == b, full set).
struct PieceSpec {
  PieceKind kind = PieceKind::segment;
  int loop = 0;  ///< 0: the outer boundary; k >= 1: scatterer k
  ExactReal ax, ay, bx, by;
  ExactReal cx, cy, rho;  ///< arc (cx, cy: an ellipse's centre too)
  ExactReal ea, eb;       ///< ellipse: semi-axes along x and y
  bool clockwise = true;  ///< arc: runs clockwise about its centre
  bool full = false;      ///< arc: the whole circle
  ExactReal span;         ///< arc: its angle, (0, 2 pi]
  ExactReal length;
  /// An arc is focusing when the table lies inside its circle: a clockwise arc of the outer boundary, an
  /// anticlockwise one elsewhere never (a scatterer's arc is dispersing). Equivalently: clockwise.
  bool focusing() const { return kind == PieceKind::arc && clockwise; }
};

/// One closed loop: pieces [first, first + count) in the order s meets them; s = 0 lies `origin` (a length)
/// along the first piece.
struct LoopSpec {
  int first = 0, count = 0;
  ExactReal origin;
  ExactReal length;
};

/// A table: its loops and pieces (checked closed and consistent by finish()), its name and the parameters it
/// was made from (for summaries and errors), its exact area and boundary length.
class TableSpec {
 public:
  std::string name;                                       ///< "stadium", "mushroom", ..., "custom"
  std::vector<std::pair<std::string, ExactReal>> params;  ///< what it was made from, in order
  std::vector<PieceSpec> pieces;
  std::vector<LoopSpec> loops;
  ExactReal area;       ///< the table's area (inside the outer loop, outside every scatterer)
  ExactReal perimeter;  ///< |boundary|: every loop's length

  /// Starts a new loop (the outer boundary first); its origin lies `origin` along its first piece.
  void begin_loop(const ExactReal& origin = ExactReal());
  /// Appends a segment from (ax, ay) to (bx, by) to the current loop.
  void segment(const ExactReal& ax, const ExactReal& ay, const ExactReal& bx, const ExactReal& by);
  /// Appends an arc of the circle (cx, cy, rho) from (ax, ay) to (bx, by), clockwise or not.
  void arc(const ExactReal& cx, const ExactReal& cy, const ExactReal& rho, const ExactReal& ax, const ExactReal& ay,
           const ExactReal& bx, const ExactReal& by, bool clockwise);
  /// Appends a whole circle, starting (and ending) at its top (cx, cy + rho), clockwise or not.
  void circle(const ExactReal& cx, const ExactReal& cy, const ExactReal& rho, bool clockwise);
  /// Appends a whole ellipse about (cx, cy) with semi-axes a along x and b along y, starting (and ending) at its top
  /// (cx, cy + b), clockwise or not; alone in its loop, whose origin is that top.
  void ellipse(const ExactReal& cx, const ExactReal& cy, const ExactReal& a, const ExactReal& b, bool clockwise);
  /// Checks the table (each loop closed, each arc's ends on its circle, the outer loop clockwise and every other
  /// anticlockwise, sizes within bounds) and works out the lengths, the area and the perimeter. Throws
  /// std::invalid_argument naming the table and what is wrong.
  void finish();
};

/// The Bunimovich stadium: straight edges y = +-r for |x| <= d/2, arcs of radius r about (+-d/2, 0); s = 0 at the
/// top edge's midpoint, clockwise (the convention of the stadium engines: geometry/stadium.hpp).
TableSpec stadium_table(const ExactReal& d, const ExactReal& r);
/// The circle of radius rho about the origin; s = 0 at its top, clockwise.
TableSpec circle_table(const ExactReal& rho);
/// The ellipse x^2 / a^2 + y^2 / b^2 <= 1; s = 0 at its top (0, b), clockwise, s = 1/4 at (a, 0).
TableSpec ellipse_table(const ExactReal& a, const ExactReal& b);
/// A mushroom (Bunimovich; Dettmann & Georgiou 2011): a half disc of radius R above y = 0 (the cap) on a stem of
/// width w <= 2 R and height h below it, centred; s = 0 at the cap's top, clockwise.
TableSpec mushroom_table(const ExactReal& R, const ExactReal& w, const ExactReal& h);
/// The Sinai billiard: the square [-a/2, a/2]^2 with a disc of radius rho at its centre (rho < a/2); the square's s
/// from its top edge's midpoint clockwise, the disc's from its top anticlockwise.
TableSpec sinai_table(const ExactReal& a, const ExactReal& rho);
/// An annulus: the circle of radius R about the origin with a disc of radius rho about (delta, 0) inside it
/// (|delta| + rho < R); s = 0 at each circle's top.
TableSpec annulus_table(const ExactReal& R, const ExactReal& rho, const ExactReal& delta);
/// A lemon: the overlap of two discs of radius R whose centres (+-delta/2, 0) lie delta apart (0 < delta < 2 R);
/// s = 0 at its top corner (0, h), clockwise.
TableSpec lemon_table(const ExactReal& R, const ExactReal& delta);
/// The triangular Lorentz gas's fundamental domain: the equilateral triangle (-1/2, 0), (0, sqrt(3)/2), (1/2, 0)
/// (side 1, the lattice's spacing) less a disc of radius r about each vertex (0 < r < 1/2): three dispersing arcs
/// and three segments, whose reflections unfold it into the gas; finite horizon for r > sqrt(3)/4. s = 0 at the
/// top arc's midpoint, clockwise.
TableSpec lorentz_table(const ExactReal& r);
/// A polygon from its vertices in clockwise order (at least 3, at most kMaxTablePieces); s = 0 at the first.
TableSpec polygon_table(const std::vector<std::pair<ExactReal, ExactReal>>& vertices);

/// A standard table by name: the parameters it takes (the keys of a scene's [table], in the constructor's order)
/// and its constructor. The polygon takes its vertices instead (no parameters here, build unset).
struct TableKind {
  std::string name;
  std::vector<std::string> params;
  TableSpec (*build)(const std::vector<ExactReal>& values) = nullptr;
};
/// Every standard table: stadium, circle, ellipse, mushroom, sinai, annulus, lemon, lorentz, polygon.
const std::vector<TableKind>& table_kinds();
/// The kind named `name`, or null.
const TableKind* find_table_kind(const std::string& name);

}  // namespace rotleak
