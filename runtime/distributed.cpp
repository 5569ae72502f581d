#include "runtime/distributed.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>

#include "core/image_neighbourhood.h"

#ifdef PL_WITH_MPI
#include <mpi.h>
#endif

namespace pl {

namespace {
constexpr size_t kChunkPixels = 64;
}

#ifdef PL_WITH_MPI

namespace {
// MPI starts only under a launcher (mpirun, srun): its set-up costs a
// third of a second, which every other run would pay.
bool active = false;
bool launchedByMpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
        if (std::getenv(name)) return true;
    return false;
}

int thisRank = 0, rankCount = 1;

// Whether MPI lets a second thread call it (ChunkDealer; else chunks are
// dealt round the ranks).
bool threadsServed = false;

// This rank's time in communication (waiting for the others included).
double secondsCommunicating = 0;
class CommunicationTimer {
public:
    CommunicationTimer() : start_(std::chrono::steady_clock::now()) {}
    ~CommunicationTimer() {
        secondsCommunicating += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    std::chrono::steady_clock::time_point start_;
};

// Messages of any size (MPI counts are ints): pieces of at most 1 GiB, at
// least one.
constexpr size_t kPieceBytes = size_t(1) << 30;
void sendBytes(const void* data, size_t size, int to, int tag) {
    size_t offset = 0;
    do {
        MPI_Send(static_cast<const char*>(data) + offset, int(std::min(kPieceBytes, size - offset)), MPI_BYTE, to, tag,
                 MPI_COMM_WORLD);
        offset += kPieceBytes;
    } while (offset < size);
}
void receiveBytes(void* data, size_t size, int from, int tag) {
    size_t offset = 0;
    do {
        MPI_Recv(static_cast<char*>(data) + offset, int(std::min(kPieceBytes, size - offset)), MPI_BYTE, from, tag,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        offset += kPieceBytes;
    } while (offset < size);
}
void broadcastBytes(void* data, size_t size) {
    for (size_t offset = 0; offset < size; offset += kPieceBytes)
        MPI_Bcast(static_cast<char*>(data) + offset, int(std::min(kPieceBytes, size - offset)), MPI_BYTE, 0,
                  MPI_COMM_WORLD);
}
}  // namespace

Distributed::Distributed(int* argc, char*** argv) {
    active = launchedByMpi();
    if (!active) return;
    // Serialized: rank 0's ChunkDealer answers from a thread of its own
    // while the main thread renders (never both in MPI at once).
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
    threadsServed = provided >= MPI_THREAD_SERIALIZED;
    // Kept: asking MPI again would be a second thread's call while rank
    // 0's ChunkDealer answers.
    MPI_Comm_rank(MPI_COMM_WORLD, &thisRank);
    MPI_Comm_size(MPI_COMM_WORLD, &rankCount);
}
Distributed::~Distributed() {
    if (active) MPI_Finalize();
}
int Distributed::rank() { return thisRank; }
int Distributed::ranks() { return rankCount; }
bool Distributed::enabled() { return true; }
double Distributed::secondsCommunicating() { return pl::secondsCommunicating; }

namespace {
// Every rank's statistics summed on rank 0, in rank order (the same sums
// every time); the others' left as they were.
void sumStatsOnRankZero(PathStats& stats) {
    static_assert(std::is_trivially_copyable_v<PathStats>);
    if (Distributed::rank() != 0) return sendBytes(&stats, sizeof stats, 0, 2);
    for (int r = 1; r < Distributed::ranks(); ++r) {
        PathStats theirs;
        receiveBytes(&theirs, sizeof theirs, r, 2);
        stats += theirs;
    }
}
}  // namespace

void gatherOnRankZero(Film& film, PathStats& stats, const std::vector<uint32_t>& myPixels) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n == 1) return;
    CommunicationTimer timer;
    if (me != 0) {
        const uint64_t count = myPixels.size();
        sendBytes(&count, sizeof count, 0, 1);
        sendBytes(myPixels.data(), count * sizeof(uint32_t), 0, 1);
        const std::vector<char> bytes = film.packPixels(myPixels);
        sendBytes(bytes.data(), bytes.size(), 0, 1);
    }
    for (int r = 1; me == 0 && r < n; ++r) {
        uint64_t count = 0;
        receiveBytes(&count, sizeof count, r, 1);
        std::vector<uint32_t> pixels(count);
        receiveBytes(pixels.data(), count * sizeof(uint32_t), r, 1);
        std::vector<char> bytes(pixels.size() * Film::packedBytesPerPixel());
        receiveBytes(bytes.data(), bytes.size(), r, 1);
        film.unpackPixels(pixels, bytes.data());
    }
    sumStatsOnRankZero(stats);
}

namespace {
// Counts and offsets of an all-to-all exchange, in elements.
struct Exchange {
    std::vector<int> counts, offsets;
    size_t total = 0;
    explicit Exchange(const std::vector<int>& perRank) : counts(perRank), offsets(perRank.size(), 0) {
        for (size_t r = 0; r < counts.size(); ++r) {
            offsets[r] = int(total);
            total += size_t(counts[r]);
        }
    }
};
// Sends each rank its list (lists[r] to rank r) and returns what each rank
// sent this one, in rank order (receivedPerRank: how many from each).
template <class T>
std::vector<T> exchangeLists(const std::vector<std::vector<T>>& lists, std::vector<int>& receivedPerRank) {
    const int n = Distributed::ranks();
    std::vector<int> sendCounts(size_t(n), 0);
    std::vector<T> send;
    for (int r = 0; r < n; ++r) {
        sendCounts[size_t(r)] = int(lists[size_t(r)].size());
        send.insert(send.end(), lists[size_t(r)].begin(), lists[size_t(r)].end());
    }
    receivedPerRank.assign(size_t(n), 0);
    CommunicationTimer timer;
    MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receivedPerRank.data(), 1, MPI_INT, MPI_COMM_WORLD);
    const Exchange out(sendCounts), in(receivedPerRank);
    std::vector<T> received(in.total);
    MPI_Datatype element;
    MPI_Type_contiguous(int(sizeof(T)), MPI_BYTE, &element);
    MPI_Type_commit(&element);
    MPI_Alltoallv(send.data(), out.counts.data(), out.offsets.data(), element, received.data(), in.counts.data(),
                  in.offsets.data(), element, MPI_COMM_WORLD);
    MPI_Type_free(&element);
    return received;
}

// A key's residuals over the render, as rank 0 sends them to every rank.
struct KeyTotal {
    int32_t key;
    Film::Moments moments;
};
static_assert(std::is_trivially_copyable_v<KeyTotal> && std::is_trivially_copyable_v<Film::PixelResiduals> &&
              std::is_trivially_copyable_v<Film::WindowSamples>);

// Every key's residuals, added on rank 0 in pixel order (as one film adds
// them), then sent to every rank.
Film::KeyPools poolKeysOnRankZero(const Film& film, int channel, size_t pixelCount) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    Film::KeyPools keys;
    std::vector<Film::PixelResiduals> mine = film.residuals(channel);
    if (me != 0) {
        CommunicationTimer timer;
        sendBytes(mine.data(), mine.size() * sizeof(Film::PixelResiduals), 0, 5);
    } else {
        std::vector<std::vector<Film::PixelResiduals>> all(static_cast<size_t>(n));
        all[0] = std::move(mine);
        {
            CommunicationTimer timer;
            for (int r = 1; r < n; ++r) {
                all[size_t(r)].resize(pixelCountOfRank(pixelCount, r, n));
                receiveBytes(all[size_t(r)].data(), all[size_t(r)].size() * sizeof(Film::PixelResiduals), r, 5);
            }
        }
        for (uint32_t p = 0; p < pixelCount; ++p)
            Film::addResiduals(keys, all[size_t(rankOfPixel(p, n))][positionInShare(p, n)]);
    }
    std::vector<KeyTotal> table;
    for (const auto& [key, moments] : keys) table.push_back({key, moments});
    uint64_t size = table.size();
    {
        CommunicationTimer timer;
        broadcastBytes(&size, sizeof size);
        table.resize(size);
        broadcastBytes(table.data(), size * sizeof(KeyTotal));
    }
    if (me != 0)
        for (const KeyTotal& k : table) keys[k.key] = k.moments;
    return keys;
}
}  // namespace

void settleShareAcrossRanks(Film& film, int channel, const Sensor& sensor, const std::vector<uint32_t>& share) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    const size_t pixelCount = sensor.pixelCount();
    const Film::KeyPools keys = poolKeysOnRankZero(film, channel, pixelCount);
    // The pixels of other ranks in this rank's windows: asked of their
    // ranks, which answer with their samples.
    const ImageNeighbourhood near(&sensor, pixelCount);
    std::vector<std::vector<uint32_t>> asked(static_cast<size_t>(n));
    for (size_t i = 0; i < share.size(); ++i) {
        if (film.windowSamples(channel, i).kind == 0) continue;
        near.forEachNear(share[i], Film::kWindowRadius, [&](size_t q) {
            if (const int r = rankOfPixel(uint32_t(q), n); r != me) asked[size_t(r)].push_back(uint32_t(q));
        });
    }
    for (std::vector<uint32_t>& list : asked) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    std::vector<int> askedOfMe;
    const std::vector<uint32_t> toAnswer = exchangeLists(asked, askedOfMe);
    std::vector<std::vector<Film::WindowSamples>> answers(static_cast<size_t>(n));
    for (int r = 0, at = 0; r < n; ++r)
        for (int k = 0; k < askedOfMe[size_t(r)]; ++k, ++at)
            answers[size_t(r)].push_back(film.windowSamples(channel, positionInShare(toAnswer[size_t(at)], n)));
    std::vector<int> answered;
    const std::vector<Film::WindowSamples> samples = exchangeLists(answers, answered);
    // The answers come in rank order, each rank's in the order asked (by
    // pixel): found by rank, then by pixel.
    std::vector<size_t> firstOfRank(static_cast<size_t>(n) + 1, 0);
    for (int r = 0; r < n; ++r) firstOfRank[size_t(r) + 1] = firstOfRank[size_t(r)] + asked[size_t(r)].size();
    film.settleShare(channel, near, keys, share, [&](uint32_t q) {
        const int r = rankOfPixel(q, n);
        if (r == me) return film.windowSamples(channel, positionInShare(q, n));
        const std::vector<uint32_t>& list = asked[size_t(r)];
        const auto at = std::lower_bound(list.begin(), list.end(), q);
        // Every pixel a window meets was asked for.
        return at != list.end() && *at == q ? samples[firstOfRank[size_t(r)] + size_t(at - list.begin())]
                                            : Film::WindowSamples{};
    });
}

void gatherSettledOnRankZero(const Film& film, const std::vector<uint32_t>& share, Film& whole, PathStats& stats) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    CommunicationTimer timer;
    std::vector<std::vector<uint32_t>> theirs(static_cast<size_t>(n));
    for (int r = 1; me == 0 && r < n; ++r) theirs[size_t(r)] = pixelsOfRank(whole.pixelCount(), r, n);
    for (int c = 0; c < kChannels; ++c) {
        const std::vector<char> mine = film.packSettled(c);
        if (me != 0) {
            sendBytes(mine.data(), mine.size(), 0, 6);
            continue;
        }
        whole.unpackSettled(c, share, mine.data());
        for (int r = 1; r < n; ++r) {
            std::vector<char> bytes(theirs[size_t(r)].size() * Film::settledBytesPerChannel());
            receiveBytes(bytes.data(), bytes.size(), r, 6);
            whole.unpackSettled(c, theirs[size_t(r)], bytes.data());
        }
    }
    sumStatsOnRankZero(stats);
}

namespace {
constexpr int kAskTag = 7, kChunkTag = 8;
constexpr uint64_t kNoChunk = ~uint64_t(0);
}  // namespace

ChunkDealer::ChunkDealer(size_t count) : count_(count) {
    if (Distributed::ranks() > 1 && Distributed::rank() == 0 && threadsServed)
        answering_ = std::thread([this] { answerTheOtherRanks(); });
}

ChunkDealer::~ChunkDealer() {
    // Rank 0 answers until every other rank has been told there are none.
    if (Distributed::ranks() > 1 && Distributed::rank() != 0 && threadsServed)
        while (!exhausted_) next();
    if (answering_.joinable()) answering_.join();
}

void ChunkDealer::answerTheOtherRanks() {
    // Polled with short sleeps: a blocking receive would spin a core that
    // renders.
    int finished = 0;
    while (finished < Distributed::ranks() - 1) {
        int asked = 0;
        MPI_Status status;
        MPI_Iprobe(MPI_ANY_SOURCE, kAskTag, MPI_COMM_WORLD, &asked, &status);
        if (!asked) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            continue;
        }
        char nothing = 0;
        MPI_Recv(&nothing, 1, MPI_CHAR, status.MPI_SOURCE, kAskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        uint64_t chunk = nextChunk_.fetch_add(1);
        if (chunk >= count_) {
            chunk = kNoChunk;
            ++finished;
        }
        MPI_Send(&chunk, 1, MPI_UINT64_T, status.MPI_SOURCE, kChunkTag, MPI_COMM_WORLD);
    }
}

std::optional<size_t> ChunkDealer::next() {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n > 1 && !threadsServed) {  // dealt round the ranks
        const size_t chunk = nextChunk_.fetch_add(1) * size_t(n) + size_t(me);
        return chunk < count_ ? std::optional<size_t>(chunk) : std::nullopt;
    }
    if (n == 1 || me == 0) {
        const size_t chunk = nextChunk_.fetch_add(1);
        return chunk < count_ ? std::optional<size_t>(chunk) : std::nullopt;
    }
    CommunicationTimer timer;
    char nothing = 0;
    uint64_t chunk = kNoChunk;
    MPI_Send(&nothing, 1, MPI_CHAR, 0, kAskTag, MPI_COMM_WORLD);
    MPI_Recv(&chunk, 1, MPI_UINT64_T, 0, kChunkTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    exhausted_ = chunk == kNoChunk;
    return exhausted_ ? std::nullopt : std::optional<size_t>(chunk);
}

std::vector<std::vector<double>> shareBlocksByPixel(std::vector<double> mine, size_t pixelCount, int blocks) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n == 1) return {std::move(mine)};
    CommunicationTimer timer;
    std::vector<double> send;
    std::vector<int> sendCounts(size_t(n), 0), sendOffsets(size_t(n), 0);
    if (me < blocks) {
        send.resize(pixelCount);
        for (int q = 0; q < n; ++q) {
            sendCounts[size_t(q)] = int(pixelCountOfRank(pixelCount, q, n));
            sendOffsets[size_t(q)] = q == 0 ? 0 : sendOffsets[size_t(q - 1)] + sendCounts[size_t(q - 1)];
        }
        std::vector<int> filled = sendOffsets;
        for (uint32_t p = 0; p < pixelCount; ++p) {
            const int q = rankOfPixel(p, n);
            send[size_t(filled[size_t(q)]++)] = mine[p];
        }
    }
    const int own = int(pixelCountOfRank(pixelCount, me, n));
    std::vector<double> received(size_t(own) * size_t(blocks));
    std::vector<int> receiveCounts(size_t(n), 0), receiveOffsets(size_t(n), 0);
    for (int r = 0; r < blocks; ++r) {
        receiveCounts[size_t(r)] = own;
        receiveOffsets[size_t(r)] = r * own;
    }
    MPI_Alltoallv(send.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE, received.data(),
                  receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE, MPI_COMM_WORLD);
    std::vector<std::vector<double>> out(static_cast<size_t>(blocks));
    for (int r = 0; r < blocks; ++r)
        out[size_t(r)].assign(received.begin() + long(r) * own, received.begin() + long(r + 1) * own);
    return out;
}

std::vector<double> gatherOnRankZero(double mine) {
    if (!active) return {mine};
    std::vector<double> all(Distributed::rank() == 0 ? size_t(Distributed::ranks()) : 0);
    MPI_Gather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    return all;
}

std::vector<std::string> gatherTextOnRankZero(const std::string& mine) {
    const int n = Distributed::ranks(), me = Distributed::rank();
    if (n == 1) return {mine};
    if (me != 0) {
        const uint64_t size = mine.size();
        sendBytes(&size, sizeof size, 0, 3);
        sendBytes(mine.data(), size, 0, 4);
        return {};
    }
    std::vector<std::string> all{mine};
    for (int r = 1; r < n; ++r) {
        uint64_t size = 0;
        receiveBytes(&size, sizeof size, r, 3);
        std::string text(size, '\0');
        receiveBytes(text.data(), size, r, 4);
        all.push_back(std::move(text));
    }
    return all;
}

uint32_t broadcastFromRankZero(uint32_t value) {
    CommunicationTimer timer;
    if (active) MPI_Bcast(&value, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    return value;
}

void broadcastFromRankZero(Film& film, PathStats& stats) {
    if (!active || Distributed::ranks() == 1) return;
    CommunicationTimer timer;
    std::vector<uint32_t> all(film.pixelCount());
    for (size_t p = 0; p < all.size(); ++p) all[p] = uint32_t(p);
    std::vector<char> bytes = Distributed::rank() == 0 ? film.packPixels(all)
                                                       : std::vector<char>(all.size() * Film::packedBytesPerPixel());
    broadcastBytes(bytes.data(), bytes.size());
    if (Distributed::rank() != 0) film.unpackPixels(all, bytes.data());
    broadcastBytes(&stats, sizeof stats);
}

bool anyRankFailed(bool failed) {
    if (!active) return failed;
    CommunicationTimer timer;
    int mine = failed ? 1 : 0, any = 0;
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return any != 0;
}

#else

Distributed::Distributed(int*, char***) {}
Distributed::~Distributed() = default;
int Distributed::rank() { return 0; }
int Distributed::ranks() { return 1; }
bool Distributed::enabled() { return false; }
double Distributed::secondsCommunicating() { return 0; }
void gatherOnRankZero(Film&, PathStats&, const std::vector<uint32_t>&) {}
void settleShareAcrossRanks(Film&, int, const Sensor&, const std::vector<uint32_t>&) {
    throw std::logic_error("a film of a share settled without MPI");  // one process renders whole films
}
void gatherSettledOnRankZero(const Film&, const std::vector<uint32_t>&, Film&, PathStats&) {}
ChunkDealer::ChunkDealer(size_t count) : count_(count) {}
ChunkDealer::~ChunkDealer() = default;
void ChunkDealer::answerTheOtherRanks() {}
std::optional<size_t> ChunkDealer::next() {
    const size_t chunk = nextChunk_.fetch_add(1);
    return chunk < count_ ? std::optional<size_t>(chunk) : std::nullopt;
}
std::vector<std::vector<double>> shareBlocksByPixel(std::vector<double> mine, size_t, int) { return {std::move(mine)}; }
std::vector<double> gatherOnRankZero(double mine) { return {mine}; }
std::vector<std::string> gatherTextOnRankZero(const std::string& mine) { return {mine}; }
uint32_t broadcastFromRankZero(uint32_t value) { return value; }
void broadcastFromRankZero(Film&, PathStats&) {}
bool anyRankFailed(bool failed) { return failed; }

#endif

void runOnEveryRank(const std::function<void()>& work, bool acrossRanks) {
    if (!acrossRanks || Distributed::ranks() == 1) return work();
    std::string failure;
    std::exception_ptr own;
    try {
        work();
    } catch (const std::exception& e) {
        failure = *e.what() ? e.what() : "failed";
        own = std::current_exception();
    }
    if (!anyRankFailed(!failure.empty())) return;
    const std::vector<std::string> failures = gatherTextOnRankZero(failure);
    if (own && Distributed::rank() == 0) std::rethrow_exception(own);  // as it was (an interrupt stays one)
    for (size_t r = 1; r < failures.size(); ++r)
        if (!failures[r].empty()) throw std::runtime_error("MPI rank " + std::to_string(r) + ": " + failures[r]);
    throw std::runtime_error("another MPI rank failed");  // ranks other than 0 (they stay quiet)
}

std::vector<uint32_t> pixelsOfRank(size_t pixelCount, int rank, int ranks) {
    std::vector<uint32_t> pixels;
    for (size_t chunk = size_t(rank); chunk * kChunkPixels < pixelCount; chunk += size_t(ranks))
        for (size_t p = chunk * kChunkPixels; p < std::min(pixelCount, (chunk + 1) * kChunkPixels); ++p)
            pixels.push_back(uint32_t(p));
    return pixels;
}

size_t pixelCountOfRank(size_t pixelCount, int rank, int ranks) {
    const size_t chunks = (pixelCount + kChunkPixels - 1) / kChunkPixels;
    if (size_t(rank) >= chunks) return 0;
    size_t count = ((chunks - 1 - size_t(rank)) / size_t(ranks) + 1) * kChunkPixels;
    if ((chunks - 1) % size_t(ranks) == size_t(rank)) count -= chunks * kChunkPixels - pixelCount;  // the last, short
    return count;
}

int rankOfPixel(uint32_t pixel, int ranks) { return int(size_t(pixel) / kChunkPixels % size_t(ranks)); }

size_t positionInShare(uint32_t pixel, int ranks) {
    return (size_t(pixel) / kChunkPixels / size_t(ranks)) * kChunkPixels + size_t(pixel) % kChunkPixels;
}

}  // namespace pl
