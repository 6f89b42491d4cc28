// A scene's table as points to draw (rotleak.plot.table, docs/tables.md): each loop's boundary through its corners,
// where its s starts and which way it runs, and each leak where it lies at t = 0. Every point comes from the
// table's own geometry in double (Table<double>::at), so a picture shows what the engines run.
#pragma once

#include "io/json.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// The drawing of the scene's table: "kind", "area", "perimeter", "loops" (each "x", "y": about `samples` points
/// along the loop and every piece's ends, closed; "origin": the point s = 0; "direction": the unit tangent there,
/// towards growing s) and "leaks" (each "loop", "moving" (omega != 0), "x", "y": its interval at t = 0).
json table_drawing(const Scene& scene, int samples = 720);

}  // namespace rotleak
