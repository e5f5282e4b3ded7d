/* scheduler.h - the segment scheduler: pure logic, no sockets or clocks.
 *
 * A frame is cut into segments (pixel ranges, normally n whole lines) as
 * clients ask for work.  The size of each new segment comes from a tail
 * rule, a function the caller may swap: static (always n lines), smart (the
 * last n_clients/2 segments of a frame are cut in half, as in the original
 * design) or adaptive (segments shrink as the frame runs out, down to parts
 * of a line).  When no new pixels are left, segments still outstanding are
 * handed again to clients that ask, and the first result for a segment wins.
 * The dispatch policy is here too (sched_start_frame, sched_top_up): the
 * server and the simulator both follow it by calling them.  The server, the
 * tests and the simulator all drive this module directly; it includes
 * nothing of the wire (tests/cli/layers.sh checks). */
#ifndef LANRAY_SCHED_H
#define LANRAY_SCHED_H

#include <stdint.h>

#include "render/segment.h"

/* Size in pixels of the next segment, given the unassigned pixels left. */
typedef uint32_t (*SchedTailRule)(uint32_t remaining, uint32_t segment_pixels, uint32_t clients, uint32_t min_pixels);

uint32_t sched_tail_static(uint32_t remaining, uint32_t segment_pixels, uint32_t clients, uint32_t min_pixels);
uint32_t sched_tail_smart(uint32_t remaining, uint32_t segment_pixels, uint32_t clients, uint32_t min_pixels);
uint32_t sched_tail_adaptive(uint32_t remaining, uint32_t segment_pixels, uint32_t clients, uint32_t min_pixels);
/* The rules by name: sched_tail_names[i] is sched_tail_rules[i] ("static",
 * "smart", "adaptive"); the names end with NULL, as command-line choices do. */
extern const char *const sched_tail_names[];
extern const SchedTailRule sched_tail_rules[];
/* The rule of that name; NULL if unknown. */
SchedTailRule sched_tail_by_name(const char *name);

typedef struct {
    uint32_t width, height;
    uint32_t segment_lines; /* n */
    SchedTailRule tail;
    uint32_t min_pixels;    /* smallest segment the adaptive rule makes */
} SchedConfig;

typedef enum {
    SCHED_ACCEPT = 0,  /* first result for this segment: use the pixels */
    SCHED_DUPLICATE,   /* someone else delivered it first: drop */
    SCHED_STALE,       /* result for an older frame: drop */
    SCHED_UNKNOWN,     /* this client was never given this segment: a protocol violation */
} SchedResult;

typedef struct {
    uint64_t segments, reissued, duplicate_pixels;
} SchedStats;

typedef struct Sched Sched;

Sched *sched_create(const SchedConfig *cfg);
void sched_destroy(Sched *s);
/* Starts frame `frame` (all earlier assignments become stale). */
void sched_begin_frame(Sched *s, uint32_t frame);

/* Segments kept in flight at each client: one rendering and one queued
 * behind it, so that a client never waits a round trip between two (the
 * adaptive tail rule's fair share counts on it). */
#define SCHED_IN_FLIGHT 2

/* The start of a frame, as the server and the simulator do it: with
 * auto_size, segments sized by sched_auto_lines from the work and the
 * per-segment overhead measured (or simulated) over the last frame; then
 * frame `frame` begins on `clients` clients. */
void sched_start_frame(Sched *s, uint32_t frame, uint32_t clients, int auto_size, double work_us, double overhead_us);

/* Tops the client up to SCHED_IN_FLIGHT segments: assigns what it lacks
 * (fewer where nothing is left for it) into out, in the order it should
 * render them, and returns how many.  The policy: a client gets its first
 * segments with the frame (the update), and after every result from any
 * client each client is topped up again, so that segments released by a
 * client that left, or still outstanding at the frame's end, go to the
 * idle ones. */
uint32_t sched_top_up(Sched *s, int client, Segment out[SCHED_IN_FLIGHT]);
/* Pipelined frames: two frames in flight, the older one to be shown first
 * and the newer one started when the older has no fresh work left (below),
 * so that clients with nothing left of the older render the newer rather
 * than idle or duplicate.  Tops the client up to SCHED_IN_FLIGHT segments
 * over both (newer NULL: one frame, as sched_top_up; older NULL: the
 * client cannot render the older frame, it joined after the newer began):
 * fresh work of the older, then of the newer, then outstanding segments
 * again, the older's first.  from[k] is the frame out[k] belongs to. */
uint32_t sched_top_up_pair(Sched *older, Sched *newer, int client, Segment out[SCHED_IN_FLIGHT],
                           Sched *from[SCHED_IN_FLIGHT]);
/* Fresh work is left: pixels nobody was given, or a segment whose holders
 * all left.  A frame without any is the moment to start the next. */
int sched_has_fresh(const Sched *s);
/* Gives client fresh work only (no segment again that someone holds). */
int sched_assign_fresh(Sched *s, int client, Segment *out);
/* Changes the segment size from the next frame on (automatic sizing). */
void sched_set_segment_lines(Sched *s, uint32_t lines);
/* The frame size of the frames to come (a render scale changes it between
 * frames; between frames only).  0 where a side is 0. */
int sched_set_size(Sched *s, uint32_t width, uint32_t height);

/* The automatic segment size, in lines, for a frame of `work_us` of render
 * time (0: nothing measured yet) on `clients` clients, where one segment
 * costs `overhead_us` besides its rendering (scheduler.c says why this
 * size); the server calls it with what it measures, the simulator with
 * what it simulates. */
uint32_t sched_auto_lines(double work_us, double overhead_us, uint32_t height, uint32_t clients);
/* The number of clients connected, for the tail rules. */
void sched_set_clients(Sched *s, uint32_t clients);
/* Gives client a segment: a new one while pixels are left, else one still
 * outstanding that it does not hold (fewest holders first; then one queued
 * behind another segment at its holders; then the newest).  Returns 0 when
 * there is nothing for it. */
int sched_assign(Sched *s, int client, Segment *out);
SchedResult sched_complete(Sched *s, int client, uint32_t frame, Segment seg);
/* What sched_complete would answer, changing nothing (the server decodes
 * a coded segment into the frame only where it is to be accepted). */
SchedResult sched_check(const Sched *s, int client, uint32_t frame, Segment seg);
/* The client is gone: it holds nothing any more. */
void sched_release(Sched *s, int client);
int sched_frame_done(const Sched *s);
/* Segments the client holds for the current frame. */
uint32_t sched_held(const Sched *s, int client);
uint32_t sched_frame(const Sched *s);
const SchedConfig *sched_config(const Sched *s);
SchedStats sched_stats(const Sched *s);
/* The statistics of two schedulers together (the frames' schedulers take
 * turns where frames are pipelined). */
static inline SchedStats sched_stats_sum(SchedStats a, SchedStats b)
{
    return (SchedStats){a.segments + b.segments, a.reissued + b.reissued, a.duplicate_pixels + b.duplicate_pixels};
}

#endif
