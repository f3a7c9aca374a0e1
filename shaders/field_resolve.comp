#version 460
#extension GL_GOOGLE_include_directive : require
#define FIELD_SEARCH_GATED
#include "common.glsl"
#include "field.glsl"
// One resolution pass over the round's darts (cells: point, key, leaf; words1: their states,
// DART_*; words0: each fresh leaf's first dart, the leaf's slot). An undecided dart is rejected if
// an earlier one (by key, then index) in conflict is accepted, accepted if every earlier one in
// conflict is rejected, else left undecided and counted. States only go from undecided to final,
// so a pass may read states this pass has set.
//
// Two darts of one leaf conflict under every rule, so a leaf accepts one dart at most, and of its
// undecided darts only the first to arrive may be accepted: its head. Summaries per slot let a
// dart read a leaf in a step or two rather than every dart in it (a leaf where r is large takes
// hundreds): words2, the leaf's accepted dart + 1 (0: none yet; reset by field_first_darts), and
// in target two pairs of regions of p2 words each, (the least key of the leaf's undecided darts,
// that key again if two of them share it), as the pass begins. The pass reads pair p1 ^ 1 and
// writes pair p1 (filled with ~0 before it) for the next. p0 = 1: the pass before the first, which
// only writes pair p1.
//
// p3: the darts a pass reads. 0: every dart (the item); k = 1 or 2: work list k - 1, the darts the
// pass before left undecided, in target after the pairs (its length in counter slot
// FIELD_COUNTER_WORK + 4 (k - 1) + 3, dispatched indirectly from that slot by work_args.comp,
// its item work_item()). Each dart a pass leaves
// undecided goes into the other list (list 0 after p3 = 0), so that a pass costs what is left
// of the round, not the round (llvmpipe runs a kernel's whole code for each SIMD batch, decided
// darts or not).
//
// A dart that is not its leaf's head only looks for an accepted dart of a nearby leaf (reject) and
// then waits. A head reads each other leaf's accepted dart, skips a leaf whose undecided darts all
// arrive after it, and otherwise tests the leaf's darts, waiting without a full answer if the leaf
// holds more than kScan of them and one surely arrives before the head. The first undecided dart
// of the round never waits, so the passes end. Every dart's search enters only the subtrees that
// hold a dart arriving before it and lie within the rule's reach (FieldGate): the pass before
// the first writes each inner node's least key.
const uint kScan = 32u;

FieldWords pair_word(uint pair, uint which) {
    return FieldWords(a.target + uint64_t(2u * pair + which) * uint64_t(a.p2) * 4u);
}

FieldWords work_list(uint k) { return FieldWords(a.target + uint64_t(4u + k) * uint64_t(a.p2) * 4u); }

// Dart j's r (field_first_darts.comp).
uint dart_radius(uint j) { return field_dart_radii(a.target, a.p2).value[j]; }

// Counts dart (key) among the undecided darts of the leaf at `slot` for the next pass.
void record(uint slot, uint key) {
    if (atomicMin(pair_word(a.p1, 0u).value[slot], key) == key) atomicMin(pair_word(a.p1, 1u).value[slot], key);
}

// Resolves dart j of the round's `count` (if still undecided).
void resolve(uint j, uint count) {
    FieldWords states = FieldWords(a.words1);
    if (field_load(states, j) != DART_UNDECIDED) return;
    FieldCells darts = FieldCells(a.cells);
    FieldWords first = FieldWords(a.words0);
    uvec4 d = darts.value[j];
    uint own = first.value[d.w];
    if (a.p0 != 0u) {
        record(own, d.z);
        field_note_key(field_run(), d.xy, d.z);
        return;
    }
    FieldWords accepted = FieldWords(a.words2);
    FieldWords least = pair_word(a.p1 ^ 1u, 0u);
    bool head = least.value[own] == d.z;
    // Two undecided darts of the leaf share the least key: the leaf's darts are tested in full.
    bool tied = head && pair_word(a.p1 ^ 1u, 1u).value[own] == d.z;
    bool rejected = field_load(accepted, own) != 0u;
    bool wait = !head;
    FieldRun run = field_run();
    FieldBudget budget = FieldBudget(run.budget, 0u);
    if (!rejected) {
        uint r = dart_radius(j);
        FieldSearch s = field_run_search(run, d.xy, d.xy, uint64_t(field_reach(run, d.xy, d.xy, r)), FIELD_FRESH, budget);
        // Only the subtrees with a dart that arrives before this one, within the rule's reach.
        field_run_gate(run, s, d.xy, r, 0u);
        field_search_gate_key(s, run.keys, d.z);
        for (uint leaf = field_search_next(run.tree, s); leaf < FIELD_SEARCH_OVERFLOW && !rejected;
             leaf = field_search_next(run.tree, s)) {
            bool mine = leaf == d.w;
            if (mine && !tied) continue;
            uint slot = first.value[leaf];
            uint taken = field_load(accepted, slot);
            if (taken != 0u && !mine) {
                // The leaf's other darts are rejected, or will be.
                uvec4 o = darts.value[taken - 1u];
                rejected = arrives_before(o.z, taken - 1u, d.z, j) &&
                           field_conflict(rule_f(run.rule, dart_radius(taken - 1u), r),
                                          distance2(run.lattice, o.xy, d.xy));
                continue;
            }
            uint lead = least.value[slot];
            if (!head || (!mine && lead > d.z)) continue;
            bool capped = !mine && lead < d.z;
            for (uint k = slot; k < count; k++) {
                uvec4 o = darts.value[k];
                if (o.w != leaf) break;
                if (s.steps++ >= s.budget) break;
                if (capped && k - slot == kScan) {
                    wait = true;
                    break;
                }
                if (!arrives_before(o.z, k, d.z, j)) continue;
                uint state = field_load(states, k);
                if (state == DART_REJECTED) continue;
                if (!mine &&
                    !field_conflict(rule_f(run.rule, dart_radius(k), r), distance2(run.lattice, o.xy, d.xy)))
                    continue;
                if (state == DART_ACCEPTED) {
                    rejected = true;
                    break;
                }
                wait = true;
                // The head waits whatever else the leaf holds; an accepted dart of it shows in
                // words2 in a later pass.
                if (!mine) break;
            }
        }
        // A head's search must be whole; another dart's only looks for an accepted dart in
        // conflict, and without one by the budget's end waits.
        if (head) {
            field_run_spend(s, budget);
            field_note_budget(budget);
        }
    }
    if (budget.overflow != 0u) return;
    if (rejected) {
        field_store(states, j, DART_REJECTED);
    } else if (!wait) {
        field_store(states, j, DART_ACCEPTED);
        field_store(accepted, own, j + 1u);
    } else {
        FieldWords counters = FieldWords(a.counters);
        atomicAdd(counters.value[FIELD_COUNTER_UNDECIDED], 1u);
        uint next = a.p3 == 1u ? 1u : 0u;
        work_list(next).value[atomicAdd(counters.value[FIELD_COUNTER_WORK + 4u * next + 3u], 1u)] = j;
        record(own, d.z);
    }
}

// One call of resolve(), which the compiler inlines: a second would double the kernel's code.
void main() {
    uint count = field_value(a.count);
    bool all = a.p3 == 0u;
    uint k = all ? field_item() : work_item();
    uint listed = all ? count : FieldWords(a.counters).value[FIELD_COUNTER_WORK + 4u * (a.p3 - 1u) + 3u];
    if (k < listed) resolve(all ? k : work_list(a.p3 - 1u).value[k], count);
}
