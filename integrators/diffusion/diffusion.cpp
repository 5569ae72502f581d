#include "integrators/diffusion/diffusion.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <type_traits>

#include "media/dda.h"
#include "runtime/scheduler.h"

namespace pl {

namespace {

// How deep a column is read (mm): single scattering is spent within a few
// mean free paths of the clearest resin that scatters.
constexpr float kColumnDepth_mm = 4.0f;
// The effective medium of a column weighs its labels by e^{-z / this}: the
// light that diffuses out of a halftoned shell is coloured by the top
// layers it enters and leaves through. Measured on the greek cube against
// a converged render (docs/diffusion.md): 0.1 mm did best of 0.02-3 mm and
// of weights over a diffusion length or the first scatters' depths.
constexpr float kSurfaceLayer_mm = 0.1f;
// A cluster whose radius is under this fraction of its distance counts as
// one point at its centroid (Barnes-Hut's opening criterion).
constexpr float kOpening = 0.5f;
constexpr size_t kLeafElements = 8;
// The error the predictor reports (as sharedError: it is bias, common to
// every sample), as a share of the multiple scattering it adds: chosen so
// that 91 % of the greek cube's voxel channels lie within twice it of a
// converged render (bench's "within 2 errors"; docs/diffusion.md). Single
// scattering is exact up to the column's lateral uniformity.
constexpr float kErrorShareOfMultipleScattering = 0.5f;

// The tables of one Henyey-Greenstein g (and the scene's ior).
struct ProfileTables {
    double g;
    std::shared_ptr<const SingleScatteringDepthTable> single;
    std::shared_ptr<const BeamDiffusionTable> multiple;  // only for a g some resin scatters with
};

// The tables of (g, ior), made once per process: an optimisation loop
// makes a predictor per iteration, and the multiple-scattering table takes
// a few tenths of a second.
template <class Table>
std::shared_ptr<const Table> sharedTable(double g, double ior) {
    static std::mutex mutex;
    static std::map<std::pair<double, double>, std::shared_ptr<const Table>> tables;
    std::lock_guard<std::mutex> lock(mutex);
    std::shared_ptr<const Table>& table = tables[{g, ior}];
    if (!table) {
        if constexpr (std::is_same_v<Table, BeamDiffusionTable>)
            table = std::make_shared<const Table>(g, ior, BeamDiffusionTable::Parts::MultipleMatchedToHalfSpace);
        else
            table = std::make_shared<const Table>(g, ior);
    }
    return table;
}

// A surface element: a surface voxel's patch, and the effective medium of
// its column per channel.
struct Element {
    Point3f p;
    float area_mm2 = 0;
    RGB sigmaT_perMm{0, 0, 0}, sigmaS_perMm{0, 0, 0};
    std::array<uint16_t, kChannels> table{0, 0, 0};  // the multiple-scattering table per channel
};

// Elements grouped by space (median splits along the widest axis), each
// node with its total area, its area-weighted centroid and media, and the
// radius that holds its elements.
class ClusterTree {
public:
    explicit ClusterTree(const std::vector<Element>& elements) : elements_(elements) {
        order_.resize(elements.size());
        for (size_t i = 0; i < order_.size(); ++i) order_[i] = uint32_t(i);
        nodes_.reserve(2 * elements.size() / kLeafElements + 1);
        if (!elements.empty()) build(0, uint32_t(elements.size()));
    }

    // f(distance, area, spread, sigmaT, sigmaS) for every element but
    // `self`, or a cluster of them standing for its elements as seen from
    // x: the spread is the mean squared distance of its area from its
    // centroid (mm^2; an element is a square of its area).
    template <class F>
    void forEachSource(const Point3f& x, size_t self, F&& f) const {
        if (nodes_.empty()) return;
        uint32_t stack[64];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            const float d = length(node.centroid - x);
            if (node.leaf) {
                for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                    const uint32_t j = order_[k];
                    if (j == self) continue;
                    const Element& e = elements_[j];
                    f(length(e.p - x), e.area_mm2, e.area_mm2 / 6.0f, e.sigmaT_perMm, e.sigmaS_perMm);
                }
            } else if (node.radius_mm < kOpening * d) {
                f(d, node.area_mm2, node.spread_mm2, node.sigmaT_perMm, node.sigmaS_perMm);
            } else {
                stack[top++] = node.left;
                stack[top++] = node.right;
            }
        }
    }

private:
    struct Node {
        Point3f centroid;
        float radius_mm = 0, area_mm2 = 0, spread_mm2 = 0;
        RGB sigmaT_perMm{0, 0, 0}, sigmaS_perMm{0, 0, 0};
        uint32_t first = 0, count = 0, left = 0, right = 0;
        bool leaf = false;
    };

    uint32_t build(uint32_t first, uint32_t count) {
        const uint32_t index = uint32_t(nodes_.size());
        nodes_.emplace_back();
        Node node;
        node.first = first;
        node.count = count;
        Point3f lo(1e30f, 1e30f, 1e30f), hi(-1e30f, -1e30f, -1e30f), weighted(0, 0, 0), mean(0, 0, 0);
        for (uint32_t k = first; k < first + count; ++k) {
            const Element& e = elements_[order_[k]];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], e.p[a]);
                hi[a] = std::max(hi[a], e.p[a]);
            }
            node.area_mm2 += e.area_mm2;
            weighted += e.p * e.area_mm2;
            mean += e.p;
            for (int c = 0; c < kChannels; ++c) {
                node.sigmaT_perMm[c] += e.area_mm2 * e.sigmaT_perMm[c];
                node.sigmaS_perMm[c] += e.area_mm2 * e.sigmaS_perMm[c];
            }
        }
        node.centroid = node.area_mm2 > 0 ? weighted / node.area_mm2 : mean / float(count);
        for (int c = 0; c < kChannels; ++c) {
            node.sigmaT_perMm[c] = node.area_mm2 > 0 ? node.sigmaT_perMm[c] / node.area_mm2 : 0.0f;
            node.sigmaS_perMm[c] = node.area_mm2 > 0 ? node.sigmaS_perMm[c] / node.area_mm2 : 0.0f;
        }
        double secondMoment = 0;
        for (uint32_t k = first; k < first + count; ++k) {
            const Element& e = elements_[order_[k]];
            const Vec3f d = e.p - node.centroid;
            node.radius_mm = std::max(node.radius_mm, length(d));
            // Each element itself a square of its area (w^2 / 6 about its centre).
            secondMoment += e.area_mm2 * (dot(d, d) + e.area_mm2 / 6.0f);
        }
        if (node.area_mm2 > 0) node.spread_mm2 = float(secondMoment / node.area_mm2);
        if (count <= kLeafElements) {
            node.leaf = true;
        } else {
            const Vec3f extent = hi - lo;
            const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
            const uint32_t half = count / 2;
            std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                             [&](uint32_t a, uint32_t b) {
                                 const float pa = elements_[a].p[axis], pb = elements_[b].p[axis];
                                 return pa < pb || (pa == pb && a < b);
                             });
            node.left = build(first, half);
            node.right = build(first + half, count - half);
        }
        nodes_[index] = node;
        return index;
    }

    const std::vector<Element>& elements_;
    std::vector<uint32_t> order_;
    std::vector<Node> nodes_;
};

// The profile tables, one pair per Henyey-Greenstein g of the labels, and
// per channel and label the index of its pair.
struct LabelProfiles {
    std::vector<ProfileTables> tables;
    std::array<std::array<uint16_t, 256>, kChannels> tableOfLabel{};
};

LabelProfiles labelProfilesOf(const LabelMedium& medium, float ior) {
    LabelProfiles out;
    std::vector<ProfileTables>& tables = out.tables;
    float mostSigmaS = 0;
    for (int c = 0; c < kChannels; ++c)
        for (int l = 0; l < 256; ++l)
            mostSigmaS = std::max(mostSigmaS, medium.lut(c).sigmaT_perMm[l] * medium.lut(c).albedo[l]);
    for (int c = 0; c < kChannels; ++c)
        for (int l = 0; l < 256; ++l) {
            const ChannelLut& lut = medium.lut(c);
            if (!(lut.sigmaT_perMm[l] > 0)) continue;
            auto same = std::find_if(tables.begin(), tables.end(), [&](const ProfileTables& t) { return t.g == lut.g[l]; });
            if (same == tables.end()) {
                tables.push_back({lut.g[l], sharedTable<SingleScatteringDepthTable>(lut.g[l], ior), nullptr});
                same = tables.end() - 1;
            }
            out.tableOfLabel[c][l] = uint16_t(same - tables.begin());
            // Resins that hardly scatter (clear) bring no diffusion.
            if (lut.sigmaT_perMm[l] * lut.albedo[l] > 1e-3f * mostSigmaS && !same->multiple)
                same->multiple = sharedTable<BeamDiffusionTable>(lut.g[l], ior);
        }
    return out;
}

// A run of one label down an element's column, and its weight in the
// effective medium: e^{-z / kSurfaceLayer_mm} over the run.
struct ColumnSegment {
    Label label;
    float z0, z1;
    double weight;
};

// The labels down the column under surface point p along -normal (to
// the object's far side or kColumnDepth_mm), with their weights; returns
// how many segments carry weight (past the first below e^{-z /
// kSurfaceLayer_mm} = 1e-3 the rest weighs less than 0.1 %).
size_t readColumn(const Scene& scene, const Point3f& p, const Vec3f& normal, LabelMedium::Tracker& sampler,
                  std::vector<ColumnSegment>& column) {
    const LabelMedium& medium = *scene.medium;
    const Ray inward = scene.geometry->spawnRay(p, normal, -normal);
    const auto exit = scene.geometry->intersectFromInside(inward, kColumnDepth_mm);
    const float depth_mm = exit ? exit->t : kColumnDepth_mm;
    const CellRay cells = medium.toCellRay(inward);
    column.clear();
    GridDda dda(cells.o, cells.d, 0.0f, depth_mm, medium.frame().indexMin, medium.frame().indexMax());
    DdaSegment segment;
    while (dda.next(segment)) column.push_back({sampler.labelAt(segment.cell), segment.t0, segment.t1, 0.0});
    size_t weighted = 0;
    float above = column.empty() ? 0.0f : std::exp(-column.front().z0 / kSurfaceLayer_mm);
    while (weighted < column.size()) {
        const float below = std::exp(-column[weighted].z1 / kSurfaceLayer_mm);
        column[weighted++].weight = above - below;
        above = below;
        if (below < 1e-3f) break;
    }
    return weighted;
}

// Single scattering down the column, layer by layer, in one channel.
double singleScatteringOf(const std::vector<ColumnSegment>& column, const ChannelLut& lut, const LabelProfiles& profiles,
                          int channel) {
    double tau = 0, single = 0;
    for (const ColumnSegment& s : column) {
        const SingleScatteringDepthTable& table = *profiles.tables[profiles.tableOfLabel[channel][s.label]].single;
        const double tauNext = tau + double(lut.sigmaT_perMm[s.label]) * (s.z1 - s.z0);
        single += lut.albedo[s.label] * (table.cumulative(tauNext) - table.cumulative(tau));
        tau = tauNext;
        if (tau > SingleScatteringDepthTable::kMaxOpticalDepth) break;
    }
    return single;
}

// The element's effective medium in one channel: the coefficients weighted
// by e^{-z / kSurfaceLayer_mm} down the column, and the multiple-scattering
// table of the nearest g.
void setEffectiveMedium(const std::vector<ColumnSegment>& column, size_t weighted, const ChannelLut& lut,
                        const LabelProfiles& profiles, int channel, Element& e) {
    double w = 0, wt = 0, ws = 0, wg = 0;
    for (size_t k = 0; k < weighted; ++k) {
        const ColumnSegment& s = column[k];
        const double st = lut.sigmaT_perMm[s.label], ss = st * lut.albedo[s.label];
        w += s.weight;
        wt += s.weight * st;
        ws += s.weight * ss;
        wg += s.weight * ss * lut.g[s.label];
    }
    const float sigmaT = w > 0 ? float(wt / w) : 0.0f, sigmaS = w > 0 ? float(ws / w) : 0.0f;
    const float g = ws > 0 ? float(wg / ws) : 0.0f;
    e.sigmaT_perMm[channel] = sigmaT;
    e.sigmaS_perMm[channel] = sigmaS;
    float nearest = 1e30f;
    const std::vector<ProfileTables>& tables = profiles.tables;
    for (size_t t = 0; t < tables.size(); ++t)
        if (tables[t].multiple && std::abs(float(tables[t].g) - g) < nearest) {
            nearest = std::abs(float(tables[t].g) - g);
            e.table[channel] = uint16_t(t);
        }
}

// Multiple scattering at element i: the profile summed over the surface
// around it (its own patch as a disc of its area), in the medium averaged
// between the two columns.
std::array<double, kChannels> multipleScatteringAt(size_t i, const std::vector<Element>& elements,
                                                   const ClusterTree& tree, const std::vector<ProfileTables>& tables) {
    const Element& e = elements[i];
    std::array<double, kChannels> sum{0, 0, 0};
    auto add = [&](float r_mm, float area_mm2, float spread_mm2, const RGB& sigmaT, const RGB& sigmaS) {
        for (int c = 0; c < kChannels; ++c) {
            const BeamDiffusionTable* table = tables[e.table[c]].multiple.get();
            if (!table) continue;
            const float st = 0.5f * (e.sigmaT_perMm[c] + sigmaT[c]), ss = 0.5f * (e.sigmaS_perMm[c] + sigmaS[c]);
            if (st > 0) sum[c] += area_mm2 * table->spreadProfile_perMm2(ss / st, st, r_mm, spread_mm2);
        }
    };
    const float ownRadius_mm = std::sqrt(e.area_mm2 / kPi);
    for (int c = 0; c < kChannels; ++c) {
        const BeamDiffusionTable* table = tables[e.table[c]].multiple.get();
        if (table && e.sigmaT_perMm[c] > 0)
            sum[c] += table->withinRadius(e.sigmaS_perMm[c] / e.sigmaT_perMm[c], e.sigmaT_perMm[c], ownRadius_mm);
    }
    tree.forEachSource(e.p, i, add);
    return sum;
}

}  // namespace

Diffusion::Diffusion(const Scene& scene, const Sensor& sensor) : SurfaceResponse(scene, sensor) {
    const LabelMedium& medium = *scene.medium;
    const size_t n = elementCount();
    const LabelProfiles profiles = labelProfilesOf(medium, scene.ior);
    std::vector<Element> elements(n);
    single_.assign(n, RGB{0, 0, 0});
    multiple_.assign(n, RGB{0, 0, 0});
    if (profiles.tables.empty()) return;  // nothing in the object scatters
    // Each element's column: single scattering and the effective medium.
    parallelForTiles(n, 256, [&](size_t begin, size_t end) {
        LabelMedium::Tracker sampler(medium);
        std::vector<ColumnSegment> column;
        for (size_t i = begin; i < end; ++i) {
            const SurfacePoint geometry = surfacePoint(i);
            Element& e = elements[i];
            e.p = geometry.p;
            e.area_mm2 = geometry.area_mm2;
            const size_t weighted = readColumn(scene, e.p, geometry.normal, sampler, column);
            for (int c = 0; c < kChannels; ++c) {
                single_[i][c] = float(singleScatteringOf(column, medium.lut(c), profiles, c));
                setEffectiveMedium(column, weighted, medium.lut(c), profiles, c, e);
            }
        }
    });
    const ClusterTree tree(elements);
    parallelForTiles(n, 256, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const std::array<double, kChannels> sum = multipleScatteringAt(i, elements, tree, profiles.tables);
            for (int c = 0; c < kChannels; ++c) multiple_[i][c] = float(sum[c]);
        }
    });
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < kChannels; ++c) {
            response_[i][c] = single_[i][c] + multiple_[i][c];
            errorBound_[i][c] = kErrorShareOfMultipleScattering * multiple_[i][c];
        }
    coverElementsOverClearResin();
}

std::unique_ptr<Integrator> Diffusion::create(const Scene& scene, const Sensor& sensor, const RenderSettings&) {
    return std::make_unique<Diffusion>(scene, sensor);
}

}  // namespace pl
