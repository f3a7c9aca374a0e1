// The sampling domain as every kernel sees it: the radius model (radii.h), the lattice
// (lattice.h) and the base grid over it (paper section 1; Ebeida et al.'s flat quadtree). Base
// cells are squares of 2^cell_bits lattice units whose diagonal is shorter than the smallest
// inhibition radius, so a base cell holds at most one sample and a sample covers its whole base cell.
#ifndef VRPD_DOMAIN_H
#define VRPD_DOMAIN_H
#include "bridge.h"
#include "lattice.h"
#include "radii.h"

VRPD_BEGIN

// Crosses the bus inside push constants (kernels.h), so it stays at 48 bytes: CellArgs fills the
// 128 bytes every Vulkan device guarantees.
struct Domain {
    Radii radii;
    Lattice lattice;
    uint cells_x;          // base cells per row
    uint cells_y;
    uint cell_bits;        // base cell side = 1 << cell_bits lattice units
};
#ifdef __cplusplus
static_assert(sizeof(Domain) == 48 && offsetof(Domain, lattice) == 24 && offsetof(Domain, cells_x) == 36 &&
              offsetof(Domain, cell_bits) == 44);
#endif

// Squared gap between a base cell and the one (dx, dy) cells away: no point of the two is nearer.
VRPD_FN uint64_t cell_gap2(Domain dom, int dx, int dy) {
    uint side = 1u << dom.cell_bits;
    uint ax = uint(dx < 0 ? -dx : dx);
    uint ay = uint(dy < 0 ? -dy : dy);
    uint64_t gx = ax == 0u ? uint64_t(0) : uint64_t(ax - 1u) * uint64_t(side) + uint64_t(1);
    uint64_t gy = ay == 0u ? uint64_t(0) : uint64_t(ay - 1u) * uint64_t(side) + uint64_t(1);
    return gx * gx + gy * gy;
}

VRPD_FN uvec2 base_cell_of(Domain dom, uvec2 p) { return uvec2(p.x >> dom.cell_bits, p.y >> dom.cell_bits); }
VRPD_FN uint base_index(Domain dom, uvec2 cell) { return cell.y * dom.cells_x + cell.x; }
VRPD_FN uint base_of_point(Domain dom, uvec2 p) { return base_index(dom, base_cell_of(dom, p)); }
// The lattice corner of base cell b.
VRPD_FN uvec2 base_corner(Domain dom, uint b) {
    return uvec2((b % dom.cells_x) << dom.cell_bits, (b / dom.cells_x) << dom.cell_bits);
}

VRPD_END
#endif
