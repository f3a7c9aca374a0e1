// The sizing-field sampler on a Vulkan device: a run, from its upload to its read-back, and
// FieldDevice (field_vulkan.h).
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "vulkan/field_engine.h"
#include "vulkan/field_vulkan.h"

namespace vrpd::detail {

using namespace shared;

namespace {
constexpr std::uint32_t kMaxRounds = 1000000;  // a bug guard, far above any run
}  // namespace

void FieldVulkan::place_given(const std::vector<glm::uvec2>& given, std::uint32_t stamp) {
    const std::uint64_t n = given.size();
    Buffer staging(ctx_, n * 8, true);
    std::memcpy(staging.mapped(), given.data(), n * 8);
    grow(ctx_, offsets_, active_ * 4);
    ctx_.begin();
    const VkBufferCopy all{0, 0, n * 8};
    ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), staging.handle(), points_.handle(), 1, &all);
    // No cell took a dart: the refinement's dart offsets are all 0.
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), offsets_.handle(), 0, VK_WHOLE_SIZE, 0);
    ctx_.barrier();
    FieldArgs p = args();
    dispatch(field_place_, p, 0, n);
    ctx_.barrier();
    FieldArgs t = args();
    t.p0 = stamp;
    dispatch(field_touch_, t, 0, n);
    ctx_.barrier();
    ctx_.submit_and_wait();
    check_budget();
    samples_ = n;
    refine_list(1, 0, stamp, offsets_.address(), 0);
}

Sampling FieldVulkan::run(const FieldTable& table, const FieldQuadtree& tree, const std::vector<glm::uvec2>& given,
                          std::uint32_t first_round) {
    const auto start = std::chrono::steady_clock::now();
    if (table.kink_count != 0 && !kinks_)
        throw std::logic_error("a table with kinked cells on field kernels built without them");
    t_ = &table;
    tables_.clear();
    samples_ = darts_thrown_ = thrown_ = 0;
    least_bits_ = UINT32_MAX;
    run_args_ = {};
    // The table, the tree's words and every leaf as an active cell (in leaf order, as the host's;
    // as the 8-byte words of field.glsl's field_cell).
    std::vector<glm::uvec2> cells(tree.leaves());
    tree.each_leaf([&](std::uint32_t leaf, glm::uvec2 corner, std::uint32_t bits) {
        cells[leaf] = {2 * corner.x + (1u << bits), corner.y};
    });
    active_ = leaves_ = cells.size();
    capacity_ = std::max<std::uint64_t>({1024, active_ / 4, given.size()});
    std::vector<Buffer> staging;
    run_ = Buffer(ctx_, sizeof(FieldRun), true);
    ctx_.begin();
    auto words = [&](const auto& v) { return upload(v.data(), v.size() * sizeof(v[0]), staging); };
    const FieldTableView tv = t_->view();
    run_args_.table = tv;
    for (auto [member, array] : {std::pair{&FieldTableView::nodes, &t_->nodes},
                                 {&FieldTableView::patch_rank, &t_->patch_rank},
                                 {&FieldTableView::pyramid_lo, &t_->pyramid_lo},
                                 {&FieldTableView::pyramid_hi, &t_->pyramid_hi},
                                 {&FieldTableView::pyramid_start, &t_->pyramid_start},
                                 {&FieldTableView::kink_rank, &t_->kink_rank},
                                 {&FieldTableView::kinks, &t_->kinks}}) {
        tables_.push_back(words(*array));
        run_args_.table.*member = device_ref<FieldWords>(tables_.back().address());
    }
    tables_.push_back(words(t_->patched));
    run_args_.table.patched = device_ref<FieldBits>(tables_.back().address());
    tables_.push_back(words(t_->kinked));
    run_args_.table.kinked = device_ref<FieldBits>(tables_.back().address());
    tables_.push_back(upload(t_->splits.data(), t_->splits.size() * sizeof(FieldTable::Split), staging));
    run_args_.table.splits = device_ref<FieldWords>(tables_.back().address());
    roots_ = words(tree.root_words());
    nodes_ = words(tree.node_words());
    cells_ = words(cells);
    const FieldTreeView view = tree.view();
    run_args_.tree = {view.tile_bits, view.tiles_x, view.tiles_y, device_ref<FieldWords>(roots_.address()),
                      device_ref<FieldWords>(nodes_.address())};
    run_args_.lattice = t_->lattice;
    run_args_.rule = std::uint32_t(o_.sizing->rule);
    if (field_variant(run_args_.rule, t_->lattice.periodic != 0, density_) != variant_of(o_) ||
        (t_->kink_count > 0 && !kinks_))
        throw std::logic_error("a field table's box or kinks differ from the kernels'");
    run_args_.r_hi = t_->r_hi;
    run_args_.r_lo = t_->r_lo;
    // 1 / (1 - L) rounded up in 2^-16 units (a larger factor only widens the searches).
    if (t_->lipschitz < 1 && 65536.0 / (1 - t_->lipschitz) < 4294967295.0)
        run_args_.growth = std::uint32_t(std::ceil(65536.0 / (1 - t_->lipschitz)));
    run_args_.budget = budget_;
    leaf_sample_ = Buffer(ctx_, std::max<std::uint64_t>(tree.leaves(), 4) * 4, false);
    leaf_first_ = Buffer(ctx_, std::max<std::uint64_t>(tree.leaves(), 4) * 4, false);
    touched_ = Buffer(ctx_, std::max<std::uint64_t>(tree.leaves(), 4) * 4, false);
    run_args_.touched = device_ref<FieldWords>(touched_.address());
    node_keys_ = Buffer(ctx_, std::max<std::uint64_t>(tree.node_words().size() / 4, 4) * 4, false);
    run_args_.keys = device_ref<FieldWords>(node_keys_.address());
    run_args_.leaf_first = device_ref<FieldWords>(leaf_first_.address());
    points_ = Buffer(ctx_, capacity_ * 8, false);
    radii_ = Buffer(ctx_, capacity_ * 4, false);
    run_args_.leaf_sample = device_ref<FieldWords>(leaf_sample_.address());
    write_run();
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), leaf_sample_.handle(), 0, VK_WHOLE_SIZE, FIELD_NO_SAMPLE);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), touched_.handle(), 0, VK_WHOLE_SIZE, 0);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), leaf_first_.handle(), 0, VK_WHOLE_SIZE, FIELD_NO_SAMPLE);
    ctx_.vk().vkCmdFillBuffer(ctx_.recording(), counters_.handle(), 0, FIELD_COUNTER_WORDS * 4, 0);
    ctx_.barrier();
    FieldArgs h = args();
    h.cells = cells_.address();
    dispatch(field_histogram_, h, 0, active_);
    ctx_.barrier();
    ctx_.submit_and_wait();
    staging.clear();
    // Stamps: 1 for the given samples, round k's 2 + k (0: a leaf no sample has stamped).
    if (!given.empty()) place_given(given, 1);
    std::uint32_t round = 0, deepest = 0;
    while (active_ > 0) {
        if (round == kMaxRounds) throw Error("internal: the sizing-field sampler did not converge");
        const std::uint64_t first = samples_;
        const bool open = throw_and_resolve(first_round + round, round + 2);
        // Refinement, then this round's samples settle (their fresh marks cleared).
        refine_list(1, std::uint32_t(thrown_), round + 2, offsets_.address(), first, open);
        if (active_ > 0) deepest = std::max(deepest, t_->tile_bits - least_bits_);
        ++round;
    }
    Sampling s;
    s.lattice.resize(samples_);
    if (samples_ > 0) {
        Buffer copy(ctx_, samples_ * 8, true);
        ctx_.begin();
        const VkBufferCopy all{0, 0, samples_ * 8};
        ctx_.vk().vkCmdCopyBuffer(ctx_.recording(), points_.handle(), copy.handle(), 1, &all);
        ctx_.submit_and_wait();
        std::memcpy(s.lattice.data(), copy.mapped(), samples_ * 8);
    }
    ctx_.check_validation();
    s.stats.levels = deepest;
    s.stats.rounds = round;
    s.stats.darts = darts_thrown_;
    s.stats.peak_bytes = ctx_.peak_allocated_bytes();
    s.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
}

FieldDevice::FieldDevice(const SampleOptions& o, const FieldTable& field, std::uint32_t budget,
                         std::uint32_t work_groups)
    : impl_(std::make_unique<FieldVulkan>(o, field.kink_count != 0, budget, work_groups)), threads_(o.threads) {}
FieldDevice::~FieldDevice() = default;

Sampling FieldDevice::run(const FieldTable& t, std::uint64_t max_leaves, const std::vector<glm::uvec2>& given,
                          std::uint32_t first_round) {
    const auto start = std::chrono::steady_clock::now();
    ThreadPool pool(threads_);
    const FieldQuadtree tree(t, max_leaves, pool);
    const double leaves = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Sampling s = impl_->run(t, tree, given, first_round);
    // The leaves are built on the host, as for the host sampler (its phase of the same name).
    s.stats.profile.push_back({"leaves", leaves, 1});
    return s;
}

std::string FieldDevice::device_name() { return impl_->context().device_name(); }
std::uint64_t FieldDevice::round_trips() { return impl_->context().submits(); }
std::vector<PhaseTime> FieldDevice::profile() { return impl_->context().profile(); }

}  // namespace vrpd::detail
