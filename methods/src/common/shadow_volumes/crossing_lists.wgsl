// Per-pixel crossing lists that cannot overflow (`common::shadow_volumes::crossing_lists`), group
// 2 of the
// passes that use them. A list holds signed distances along a pixel's view ray: + where the ray
// enters a shadow volume (front-facing plane), − where it leaves one. Lists live back to back in
// one pool; list i occupies pool[offset[i] .. offset[i + 1]], sized by a counting pass:
//   1. count:  every plane fragment calls `crossing_count_fragment` (one atomic per fragment);
//   2. scan:   `cs_crossing_scan` turns the counts into offsets (exclusive prefix sum) and
//              records the total and the longest list; the CPU reads them and sizes the pool;
//   3. gather: the same fragments call `crossing_append` (the counts, cleared, are the cursors);
//   4. walk:   `crossing_sorted` sorts the pixel's list; `crossing_walk` (crossing_passes.wgsl)
//              walks it.
// One list per pixel and per light (`crossing_cfg.list`); needs nothing else (the scan pipeline
// is this module alone).

// Mirrors `CrossingUniform` in crossing_lists.rs (one dynamic-offset slot per light).
struct CrossingCfg {
    list: u32,   // which light's lists (0 for the scan)
    width: u32,
    height: u32,
    lists: u32,  // lights with lists (the scan covers lists × width × height)
    eye_count: u32,  // shadow volumes around the eye for this light (where the walk starts)
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(2) @binding(0) var<uniform> crossing_cfg: CrossingCfg;
// Crossings per list: the count pass's result, then (cleared) the gather's cursors.
@group(2) @binding(1) var<storage, read_write> crossing_count: array<atomic<u32>>;
// Exclusive prefix sum of the counts, one more entry than lists (the total).
@group(2) @binding(2) var<storage, read_write> crossing_offset: array<u32>;
@group(2) @binding(3) var<storage, read_write> crossing_pool: array<f32>;
// [0]: total crossings, [1]: the longest list (scan); [2]: lists whose gather did not match their
// count (walk; 0 unless the two passes rasterised different fragments), [3]: unused.
@group(2) @binding(4) var<storage, read_write> crossing_stats: array<atomic<u32>, 4>;

fn crossing_index(px: vec2<u32>) -> u32 {
    return (crossing_cfg.list * crossing_cfg.height + px.y) * crossing_cfg.width + px.x;
}

// Pass 1, per plane fragment at pixel px.
fn crossing_count_fragment(px: vec2<u32>) {
    atomicAdd(&crossing_count[crossing_index(px)], 1u);
}

// Pass 3, per plane fragment: its signed distance into the pixel's next free slot.
fn crossing_append(px: vec2<u32>, signed_distance: f32) {
    let i = crossing_index(px);
    let at = crossing_offset[i] + atomicAdd(&crossing_count[i], 1u);
    if (at < crossing_offset[i + 1u]) {
        crossing_pool[at] = signed_distance;
    }
}

const CROSSING_SCAN_THREADS: u32 = 256u;
var<workgroup> crossing_partial: array<u32, 256>;

// Pass 2, one workgroup: each thread sums a contiguous chunk of counts (the same trip count in
// every lane: lavapipe crashes on lane-varying loops in compute), the chunk sums are scanned in
// shared memory (Hillis–Steele), then each thread writes its chunk's offsets.
@compute @workgroup_size(256)
fn cs_crossing_scan(@builtin(local_invocation_index) t: u32) {
    let n = crossing_cfg.lists * crossing_cfg.width * crossing_cfg.height;
    let chunk = (n + CROSSING_SCAN_THREADS - 1u) / CROSSING_SCAN_THREADS;
    let last = max(n, 1u) - 1u;
    var sum = 0u;
    var longest = 0u;
    for (var j = 0u; j < chunk; j++) {
        let i = t * chunk + j;
        let c = select(0u, atomicLoad(&crossing_count[min(i, last)]), i < n);
        sum += c;
        longest = max(longest, c);
    }
    crossing_partial[t] = sum;
    workgroupBarrier();
    for (var s = 1u; s < CROSSING_SCAN_THREADS; s *= 2u) {
        let add = select(0u, crossing_partial[max(t, s) - s], t >= s);
        workgroupBarrier();
        crossing_partial[t] += add;
        workgroupBarrier();
    }
    var run = crossing_partial[t] - sum;
    for (var j = 0u; j < chunk; j++) {
        let i = t * chunk + j;
        if (i < n) {
            crossing_offset[i] = run;
            run += atomicLoad(&crossing_count[i]);
        }
    }
    atomicMax(&crossing_stats[1], longest);
    if (t == CROSSING_SCAN_THREADS - 1u) {
        crossing_offset[n] = crossing_partial[t];
        atomicStore(&crossing_stats[0], crossing_partial[t]);
    }
}

// Pass 4: sorts list px by distance in place and returns (first pool index, length). Lists of
// up to CROSSING_SORT_CAP crossings are merge-sorted in private memory (`crossing_merge_sort`:
// n·⌈log₂ n⌉ steps, against an insertion sort's n²/4 in rasterisation order, and private memory
// rather than the storage pool); longer ones fall back to the insertion sort in the pool.
fn crossing_sorted(px: vec2<u32>) -> vec2<u32> {
    let i = crossing_index(px);
    let base = crossing_offset[i];
    let n = crossing_offset[i + 1u] - base;
    // Unconditional: lavapipe crashes on an atomicAdd under a branch in compute.
    atomicAdd(&crossing_stats[2], select(0u, 1u, atomicLoad(&crossing_count[i]) != n));
    if (n <= CROSSING_SORT_CAP && crossing_descents(base, n) > CROSSING_FEW_DESCENTS) {
        crossing_merge_sort(base, n);
    } else {
        crossing_insertion_sort(base, n);
    }
    return vec2<u32>(base, n);
}

// A list with at most this many descents (neighbours out of order) is a few sorted runs, as
// lists come out when the planes are drawn near to far (a rasteriser appends one pixel's
// fragments in primitive order): the insertion sort finishes it in about n steps where the
// merge sort always takes n·⌈log₂ n⌉.
const CROSSING_FEW_DESCENTS: u32 = 2u;

// Neighbours of pool[base .. base + n] out of order by |distance|.
fn crossing_descents(base: u32, n: u32) -> u32 {
    var descents = 0u;
    for (var k = 1u; k < n; k++) {
        descents += select(0u, 1u, abs(crossing_pool[base + k - 1u]) > abs(crossing_pool[base + k]));
    }
    return descents;
}

// 64, not 256 (issue 33): WGSL zero-fills a private array in every invocation, whether the
// merge sort runs or not, and lavapipe keeps it in per-lane memory — 2 KiB per pixel at 256
// (measured on fence-spot 256², longest list 20: the frame ≈ 5 % faster at this size). Longer
// lists (per-triangle fallback planes) come out nearly sorted in plane order, which the
// insertion sort handles in about n steps.
const CROSSING_SORT_CAP: u32 = 64u;
// Two halves, [0, CAP) and [CAP, 2·CAP): each merge pass reads one and writes the other.
var<private> crossing_scratch: array<f32, 128>;

// Bottom-up merge sort of pool[base .. base + n] (n ≤ CROSSING_SORT_CAP) by |distance|, stable,
// flattened to one loop (lavapipe's compiler crashes on nested dynamic loops): each step either
// writes the next element of the current merge of runs [lo, mid) and [mid, hi), or moves on to
// the next pair of runs (and, past the end, to runs twice as wide in the other half).
fn crossing_merge_sort(base: u32, n: u32) {
    for (var k = 0u; k < n; k++) {
        crossing_scratch[k] = crossing_pool[base + k];
    }
    var read_half = 0u;     // the half being read
    var width = 1u;         // run length of this pass
    var lo = 0u;            // start of the current pair of runs
    var a = 0u;             // left cursor, in [lo, mid)
    var b = min(1u, n);     // right cursor, in [mid, hi)
    var written = 0u;       // next output index
    for (var step = 0u; step < 2u * n * 9u && width < n; step++) {
        let mid = min(lo + width, n);
        let hi = min(lo + 2u * width, n);
        if (written < hi) {
            let left = crossing_scratch[read_half + min(a, CROSSING_SORT_CAP - 1u)];
            let right = crossing_scratch[read_half + min(b, CROSSING_SORT_CAP - 1u)];
            let take_left = a < mid && (b >= hi || abs(left) <= abs(right));
            crossing_scratch[(CROSSING_SORT_CAP - read_half) + written] = select(right, left, take_left);
            a += select(0u, 1u, take_left);
            b += select(1u, 0u, take_left);
            written += 1u;
        } else if (hi < n) {
            lo = hi;
            a = lo;
            b = min(lo + width, n);
        } else {
            read_half = CROSSING_SORT_CAP - read_half;
            width *= 2u;
            lo = 0u;
            a = 0u;
            b = min(width, n);
            written = 0u;
        }
    }
    for (var k = 0u; k < n; k++) {
        crossing_pool[base + k] = crossing_scratch[read_half + k];
    }
}

// The fallback for lists longer than CROSSING_SORT_CAP: insertion sort in the pool, flattened
// to one loop: each step either shifts one element up or drops the held key into its hole, so a
// list of n with m inversions costs n − 1 + m steps (≤ n²/2; about n²/4 in rasterisation order).
fn crossing_insertion_sort(base: u32, n: u32) {
    var next = 1u;  // the element being inserted
    var hole = 1u;  // where it would go
    var key = crossing_pool[base + min(1u, max(n, 1u) - 1u)];
    for (var step = 0u; step < n * n && next < n; step++) {
        let prev = crossing_pool[base + max(hole, 1u) - 1u];
        if (hole > 0u && abs(prev) > abs(key)) {
            crossing_pool[base + hole] = prev;
            hole -= 1u;
        } else {
            crossing_pool[base + hole] = key;
            next += 1u;
            hole = next;
            key = crossing_pool[base + min(next, n - 1u)];
        }
    }
}
