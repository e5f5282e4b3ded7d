/* segment.h - a segment: the unit of work a frame is cut into.
 *
 * Pixels [first, first + count) of a frame, in row-major order: normally
 * whole lines, at a frame's end parts of one.  The scheduler cuts frames
 * into segments, the wire carries them, a client renders them
 * (render_span); it sits here, below all three, so that the scheduler
 * needs nothing of the wire. */
#ifndef LANRAY_SEGMENT_H
#define LANRAY_SEGMENT_H

#include <stdint.h>

typedef struct {
    uint32_t first, count;
} Segment;

#endif
