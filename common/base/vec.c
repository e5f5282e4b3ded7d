/* vec.c - the few vector routines too large to inline. */
#include "base/vec.h"

mat3 m3_rotation_xyz(vec3 deg)
{
    real k = REAL_PI / R(180);
    real cx = cos(deg.x * k), sx = sin(deg.x * k);
    real cy = cos(deg.y * k), sy = sin(deg.y * k);
    real cz = cos(deg.z * k), sz = sin(deg.z * k);
    /* Rz * Ry * Rx */
    mat3 m;
    m.r[0] = v3(cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx);
    m.r[1] = v3(sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx);
    m.r[2] = v3(-sy, cy * sx, cy * cx);
    return m;
}
