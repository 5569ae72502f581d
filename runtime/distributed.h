// Running one job across processes with MPI (Open MPI; optional at build
// time: without it there is one process). Each rank loads the scene, renders
// its part of the sensor's pixels (a dealt share, or chunks claimed by work
// stealing), and rank 0 gathers the films and writes.
// Every pixel is rendered whole by one rank with the random streams of a
// one-process render, so the result has the same bits whatever the number
// of ranks and threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/film.h"
#include "core/sensors.h"
#include "core/path_stats.h"

namespace pl {

class Distributed {
public:
    // MPI_Init / MPI_Finalize for the program's lifetime (main owns one).
    Distributed(int* argc, char*** argv);
    ~Distributed();
    Distributed(const Distributed&) = delete;
    Distributed& operator=(const Distributed&) = delete;

    static int rank();   // 0 without MPI
    static int ranks();  // 1 without MPI
    static bool enabled();  // built with MPI
    // This rank's time so far in communication, waiting for the other
    // ranks included (the load imbalance shows there).
    static double secondsCommunicating();
};

// The pixels of rank r's dealt share: chunks of 64 pixels dealt round the
// ranks (the costs of neighbouring pixels are alike; dealt chunks spread
// them). Light paths, progressive rounds and the prediction API use it.
std::vector<uint32_t> pixelsOfRank(size_t pixelCount, int rank, int ranks);
// How many pixels rank r's share holds (pixelsOfRank's size).
size_t pixelCountOfRank(size_t pixelCount, int rank, int ranks);
// The rank whose share holds pixel p, and where p stands in its list.
int rankOfPixel(uint32_t pixel, int ranks);
size_t positionInShare(uint32_t pixel, int ranks);

// Gathers every rank's pixels of `film` (each passes the pixels it
// rendered) and sums `stats` on rank 0 (the other ranks' are left as they
// were). Collective: every rank calls it.
void gatherOnRankZero(Film& film, PathStats& stats, const std::vector<uint32_t>& myPixels);

// A render whose film holds this rank's share alone (film pixel i is the
// sensor's share[i]): settles the channel with the errors that pooling a
// whole film gives (Film::poolErrors). Every key's residuals are added on
// rank 0 in pixel order and sent to all; each rank receives, of the pixels
// other ranks hold, those in its pixels' windows. Collective.
void settleShareAcrossRanks(Film& film, int channel, const Sensor& sensor, const std::vector<uint32_t>& share);

// Every rank's settled share (film pixel i is the sensor's share[i]) in
// rank 0's `whole` (a film of all the sensor's pixels), and the
// statistics summed there (rank order). Collective.
void gatherSettledOnRankZero(const Film& film, const std::vector<uint32_t>& share, Film& whole, PathStats& stats);

// Work stealing by chunks: chunks [0, count) handed out as the ranks ask
// for them, so a rank that is faster (its pixels cheaper, its node
// quicker) takes more. Rank 0 keeps the count and a thread of its own
// answers the other ranks. Collective: every rank makes one with the same
// count and asks until it gets none (its destructor does, after an
// exception). One process: 0, 1, ..., count - 1.
class ChunkDealer {
public:
    explicit ChunkDealer(size_t count);
    ~ChunkDealer();
    ChunkDealer(const ChunkDealer&) = delete;
    ChunkDealer& operator=(const ChunkDealer&) = delete;
    std::optional<size_t> next();

private:
    void answerTheOtherRanks();
    size_t count_;
    bool exhausted_ = false;  // this rank has been told there are none left
    std::atomic<size_t> nextChunk_{0};  // on rank 0
    std::thread answering_;             // on rank 0, with more than one rank
};

// Light blocks shared round the ranks (render/render.cpp): in a wave of
// `blocks` blocks, rank r < blocks has computed block r over every pixel
// (`mine`; the others pass an empty vector). Every rank receives each
// block's values at its own pixels (in pixelsOfRank's order), in block
// order. Collective. One process: {mine}.
std::vector<std::vector<double>> shareBlocksByPixel(std::vector<double> mine, size_t pixelCount, int blocks);

// Every rank's value, in rank order, on rank 0 (empty elsewhere).
// Collective.
std::vector<double> gatherOnRankZero(double mine);

// Every rank's text, in rank order, on rank 0 (empty elsewhere).
// Collective.
std::vector<std::string> gatherTextOnRankZero(const std::string& mine);

// Rank 0's value, on every rank. Collective.
uint32_t broadcastFromRankZero(uint32_t value);
// Rank 0's film (every pixel's accumulators) and statistics, on every
// rank. Collective.
void broadcastFromRankZero(Film& film, PathStats& stats);

// A failure on any rank fails them all: every rank calls it with whether it
// failed; true if any did. Collective.
bool anyRankFailed(bool failed);

// Runs `work` on every rank; if it throws on any, it throws on every rank
// (rank 0 its own exception, or "MPI rank r: ..." with another rank's
// message; the others std::runtime_error), so that rank 0 reports one line
// and no rank goes on alone. `work` must make no collective calls a
// failure could skip (a throw between lighttrace's waves leaves the other
// ranks waiting). One process, or acrossRanks false: runs it. Collective.
void runOnEveryRank(const std::function<void()>& work, bool acrossRanks = true);

}  // namespace pl
