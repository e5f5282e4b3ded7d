/* measure.h - what the server measures while it serves, apart from the
 * event loop: the per-segment overhead and packet CPU that size segments
 * automatically (sched_auto_lines), a frame's turnaround, and the figures
 * of the summary line.  Pure bookkeeping: the loop passes in the times and
 * counts it sees, so the rules here read as a whole. */
#ifndef LANRAY_MEASURE_H
#define LANRAY_MEASURE_H

#include <stdint.h>

/* The segment overhead assumed before one is measured, in microseconds. */
#define MEASURE_OVERHEAD_US 300.0

/* What one client's results tell about the gaps between them. */
typedef struct {
    double last_data;         /* when its previous result arrived */
    uint32_t last_data_frame;
    int was_full;             /* it held two segments when that result arrived */
} MeasureClient;

typedef struct {
    uint32_t warmup;          /* frames not measured for the summary */
    uint32_t frames_done, frames_started, clients_seen_max;
    double first_frame_start, last_frame_end;
    /* the automatic segment size: render time of the frame's accepted
     * results, gaps between a busy client's results, CPU per packet */
    uint64_t frame_pixels_us;
    double overhead_us, gap_sum_us;
    int overhead_known;
    uint32_t gap_samples;
    double frame_cpu, packet_cpu_us, measured_cpu;
    int frame_sent_assets;
    uint64_t frame_packets, measured_packets;
    /* a frame's turnaround: from the end of the one before to a client
     * starting to render it, over the measured frames */
    double turn_sum_us;
    uint64_t turn_samples;
    /* the summary's bases, taken where the measured frames start */
    uint64_t total_busy_us, asset_bytes, measured_bytes_base, dup_base, seg_base;
    double latency_sum; /* start to shown, over the measured frames */
    uint32_t latency_frames;
} Measure;

/* A frame starts at `now` with `clients` connected; bytes, duplicate pixels
 * and segments so far are the bases when the measured frames begin here.
 * With `sizing` (automatic segment size) the gaps of the frame before are
 * folded into the overhead, and *work_us gets the render time of that
 * frame; returns the per-segment overhead for sched_auto_lines: measured
 * (gaps smoothed over frames, plus the packet CPU twice over) or the
 * default. */
double measure_frame_start(Measure *m, double now, uint32_t clients, uint64_t bytes, uint64_t dup_pixels,
                           uint64_t segments, int sizing, double *work_us);
/* A DATA packet for `frame` (the current one is `current`) arrived at
 * `now` from a client that rendered it in render_us and held `held`
 * segments (this one included) when it came. */
void measure_data(Measure *m, MeasureClient *c, double now, uint32_t frame, uint32_t current, uint32_t render_us,
                  uint32_t held);
/* What the scheduler made of it: `counted`, its render time counts (the
 * frame is current), `accepted`, its pixels were the first. */
void measure_result(Measure *m, uint32_t render_us, int counted, int accepted);
/* Bytes of an asset sent (not counted per frame in the summary). */
void measure_asset_sent(Measure *m, uint64_t bytes);
/* The loop's CPU spent on packets in one round. */
static inline void measure_cpu(Measure *m, double seconds) { m->frame_cpu += seconds; }
/* A measured frame was shown `seconds` after it started (its view was
 * taken): the latency of the picture on screen. */
static inline void measure_latency(Measure *m, double seconds)
{
    if (m->frames_done > m->warmup) {
        m->latency_sum += seconds;
        m->latency_frames++;
    }
}
/* The frame ended at `now`. */
void measure_frame_end(Measure *m, double now);

#endif
