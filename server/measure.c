/* measure.c - see measure.h. */
#include "measure.h"

#include <math.h>

double measure_frame_start(Measure *m, double now, uint32_t clients, uint64_t bytes, uint64_t dup_pixels,
                           uint64_t segments, int sizing, double *work_us)
{
    if (m->frames_started++ == m->warmup) {
        /* the measured frames start here: statistics so far were warm-up;
         * the clock too, unless a warm-up frame ends it (measure_frame_end:
         * with pipelined frames this one starts before that one ends) */
        if (m->warmup == 0)
            m->first_frame_start = now;
        m->total_busy_us = 0;
        m->asset_bytes = 0;
        m->measured_bytes_base = bytes;
        m->dup_base = dup_pixels;
        m->seg_base = segments;
    }
    if (clients > m->clients_seen_max)
        m->clients_seen_max = clients;
    if (sizing && m->gap_samples >= 4) { /* measured overhead, smoothed over frames */
        double g = m->gap_sum_us / m->gap_samples;
        m->overhead_us = m->overhead_known ? 0.5 * m->overhead_us + 0.5 * g : g;
        m->overhead_known = 1;
    }
    double o = m->overhead_known ? fmax(m->overhead_us, 0.0) + 2 * m->packet_cpu_us : MEASURE_OVERHEAD_US;
    *work_us = (double)m->frame_pixels_us;
    m->frame_pixels_us = 0;
    m->gap_sum_us = 0;
    m->gap_samples = 0;
    return o < 1 ? 1 : o;
}

void measure_data(Measure *m, MeasureClient *c, double now, uint32_t frame, uint32_t current, uint32_t render_us,
                  uint32_t held)
{
    /* overhead sample: a client that still held another segment went straight on to it */
    if (c->was_full && c->last_data_frame == frame && frame == current) {
        double gap = (now - c->last_data) * 1e6 - render_us;
        /* negative too: a result sent late makes one gap longer and the
         * next one shorter by as much, and the mean stays right */
        if (fabs(gap) < 1e6) {
            m->gap_sum_us += gap;
            m->gap_samples++;
        }
    }
    /* turnaround sample: the client's first result of a measured frame,
     * which it began rendering render_us ago */
    if (c->last_data_frame != frame && frame == current && m->frames_done >= m->warmup && m->frames_done > 0 &&
        !m->frame_sent_assets) {
        double turn = (now - m->last_frame_end) * 1e6 - render_us;
        if (turn >= 0 && turn < 1e6) {
            m->turn_sum_us += turn;
            m->turn_samples++;
        }
    }
    m->frame_packets++;
    c->was_full = held >= 2;
    c->last_data = now;
    c->last_data_frame = frame;
}

void measure_result(Measure *m, uint32_t render_us, int counted, int accepted)
{
    if (counted) /* time spent rendering counts whether or not this copy won */
        m->total_busy_us += render_us;
    if (accepted)
        m->frame_pixels_us += render_us;
}

void measure_asset_sent(Measure *m, uint64_t bytes)
{
    m->frame_sent_assets = 1;
    m->asset_bytes += bytes;
}

void measure_frame_end(Measure *m, double now)
{
    m->frames_done++;
    m->last_frame_end = now;
    if (m->frames_done == m->warmup) /* the measured frames' clock: from the last warm-up frame shown */
        m->first_frame_start = now;
    /* smoothed over frames, as the overhead; not from a frame that sent
     * assets, whose encoding and copying (12 ms per packet with 8 new
     * clients) would take the smoothing most of a benchmark to forget; its
     * gaps go too (clients still loading them: -1.4 ms on average) */
    if (m->frame_sent_assets) {
        m->gap_sum_us = 0;
        m->gap_samples = 0;
    } else if (m->frame_packets) {
        double per = m->frame_cpu * 1e6 / (double)m->frame_packets;
        m->packet_cpu_us = m->packet_cpu_us > 0 ? 0.5 * m->packet_cpu_us + 0.5 * per : per;
    }
    if (m->frames_done > m->warmup) {
        m->measured_cpu += m->frame_cpu;
        m->measured_packets += m->frame_packets;
    }
    m->frame_cpu = 0;
    m->frame_packets = 0;
    m->frame_sent_assets = 0;
}
