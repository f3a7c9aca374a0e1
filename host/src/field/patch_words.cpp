// The patches of a sizing field's table in its words (field/patches.h): each patch's splits in
// lattice units, breadth first, and the table's bounds over their leaves.
#include <algorithm>
#include <bit>
#include <vector>

#include "patches.h"

namespace vrpd::detail {

void install_patches(FieldTable& t, const std::vector<PatchDraft>& patches, ThreadPool& pool) {
    if (patches.empty()) return;
    t.patch_count = std::uint32_t(patches.size());
    // Patch k's root is split k; its other splits follow the roots from first[k], breadth first, so
    // that each split's split children are consecutive.
    std::vector<std::uint64_t> first(patches.size() + 1, patches.size());
    for (std::size_t k = 0; k < patches.size(); ++k) first[k + 1] = first[k] + patches[k].splits.size() - 1;
    if (first.back() >> 28)
        throw Error(fmt::format("the field's patches need {} splits, more than the table's 2^28", first.back()));
    t.splits.resize(first.back());
    t.refresh_view();
    std::vector<double> too_large(patches.size(), 0.0);
    pool.parallel_for(
        patches.size(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            std::vector<std::int32_t> order;   // the patch's splits, breadth first
            std::vector<std::uint32_t> index;  // each split's index in t.splits
            for (std::size_t k = begin; k < end; ++k) {
                const PatchDraft& p = patches[k];
                order.assign(1, 0);
                index.assign(p.splits.size(), 0);
                index[0] = std::uint32_t(k);
                std::uint64_t next = first[k];
                for (std::size_t n = 0; n < order.size(); ++n) {
                    const PatchDraft::Split& s = p.splits[std::size_t(order[n])];
                    FieldTable::Split& out = t.splits[index[std::size_t(order[n])]];
                    std::uint32_t mask = 0;
                    for (int c = 0; c < 4; ++c)
                        if (s.child[c] >= 0) {
                            mask |= 1u << c;
                            index[std::size_t(s.child[c])] = std::uint32_t(next++);
                            order.push_back(s.child[c]);
                        }
                    const std::uint32_t base = mask == 0 ? 0 : index[std::size_t(s.child[std::countr_zero(mask)])];
                    out.children = base << 4 | mask;
                    for (int m = 0; m < 5; ++m) {
                        const double units = std::round(s.value[m] / t.quantum);
                        if (units >= 4294967295.0) too_large[k] = s.value[m];
                        out.mid[m] = std::max<std::uint32_t>(1, std::uint32_t(std::min(units, 4294967294.0)));
                    }
                }
                // Each split's least and greatest node: its corners', its own and its children's,
                // children first (breadth-first order reversed).
                const std::uint32_t i = p.cell % t.cells_x, j = p.cell / t.cells_x;
                std::vector<glm::uvec4> corners(p.splits.size());
                corners[0] = t.cell_nodes(i, j);
                for (const std::int32_t s : order)
                    for (int c = 0; c < 4; ++c)
                        if (p.splits[std::size_t(s)].child[c] >= 0)
                            corners[std::size_t(p.splits[std::size_t(s)].child[c])] = shared::field_child_nodes(
                                t.view(), index[std::size_t(s)], corners[std::size_t(s)], std::uint32_t(c));
                for (auto n = order.rbegin(); n != order.rend(); ++n) {
                    const PatchDraft::Split& s = p.splits[std::size_t(*n)];
                    FieldTable::Split& out = t.splits[index[std::size_t(*n)]];
                    const glm::uvec4 v = corners[std::size_t(*n)];
                    out.lo = std::min({v.x, v.y, v.z, v.w});
                    out.hi = std::max({v.x, v.y, v.z, v.w});
                    for (const std::uint32_t m : out.mid) out.lo = std::min(out.lo, m), out.hi = std::max(out.hi, m);
                    for (const std::int32_t c : s.child)
                        if (c >= 0) {
                            const FieldTable::Split& child = t.splits[index[std::size_t(c)]];
                            out.lo = std::min(out.lo, child.lo);
                            out.hi = std::max(out.hi, child.hi);
                        }
                }
            }
        },
        4);
    for (const double v : too_large)
        if (v != 0) throw Error(fmt::format("the field's radius {:.6g} is too large for the lattice of this box", v));
    std::vector<std::uint32_t> cells(patches.size());
    for (std::size_t k = 0; k < patches.size(); ++k) cells[k] = patches[k].cell;
    rank_cells(std::size_t(t.cells_x) * t.cells_y, cells, t.patched, t.patch_rank);
    t.refresh_view();
}

void patch_bounds(const FieldTable& t, BoundsPart& bounds, ThreadPool& pool) {
    const std::uint32_t last_x = t.lattice.extent_x - 1, last_y = t.lattice.extent_y - 1;
    // Each patch's table cell, in patch order.
    std::vector<std::uint32_t> cells;
    cells.reserve(t.patch_count);
    for (std::size_t w = 0; w < t.patched.size(); ++w)
        for (std::uint64_t word = t.patched[w]; word != 0; word &= word - 1)
            cells.push_back(std::uint32_t(w * 64 + std::size_t(std::countr_zero(word))));
    std::vector<BoundsPart> parts(pool.chunks(cells.size(), 4));
    pool.parallel_for(
        cells.size(),
        [&](std::size_t begin, std::size_t end, unsigned chunk) {
            BoundsPart part;
            struct Node {
                std::uint32_t split, bits;
                glm::uvec2 corner;  // in lattice units
                glm::uvec4 v;
            };
            std::vector<Node> stack;
            for (std::size_t k = begin; k < end; ++k) {
                const std::uint32_t c = cells[k], i = c % t.cells_x, j = c / t.cells_x;
                stack.assign(1,
                             {std::uint32_t(k), t.cell_bits, {i << t.cell_bits, j << t.cell_bits}, t.cell_nodes(i, j)});
                while (!stack.empty()) {
                    const Node n = stack.back();
                    stack.pop_back();
                    const std::uint32_t bits = n.bits - 1;
                    for (std::uint32_t q = 0; q < 4; ++q) {
                        const glm::uvec2 corner = n.corner + glm::uvec2((q & 1) << bits, (q >> 1) << bits);
                        const glm::uvec4 v = shared::field_child_nodes(t.view(), n.split, n.v, q);
                        const int s = shared::field_child_split(t.view(), n.split, q);
                        // Leaves wholly past a free box's lattice, where r is never read, are
                        // passed over.
                        if (corner.x > last_x || corner.y > last_y) continue;
                        if (s >= 0) {
                            stack.push_back({std::uint32_t(s), bits, corner, v});
                            continue;
                        }
                        // Over the leaf's lattice points in the box, r's extremes are at the
                        // corners of the leaf clipped to it; its gradient, in node units per
                        // table cell, is 2^(cell_bits - bits) times its own.
                        const std::uint32_t top = (1u << bits) - 1;
                        const glm::uvec2 far(std::min(top, last_x - corner.x), std::min(top, last_y - corner.y));
                        const glm::uvec2 e = shared::field_corner_extremes(v, bits, {0, 0}, far);
                        part.lo = std::min(part.lo, e.x);
                        part.hi = std::max(part.hi, e.y);
                        raise_steepest(part.steepest, v.x, v.y, v.z, v.w, double(1u << (t.cell_bits - bits)));
                    }
                }
            }
            parts[chunk] = part;
        },
        4);
    for (const BoundsPart& part : parts) bounds.join(part);
}

}  // namespace vrpd::detail
