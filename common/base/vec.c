/* vec.c - the few vector routines too large to inline. */
#include "base/vec.h"

#include "base/dmath.h"

mat3 m3_rotation_xyz(vec3 deg)
{
    real k = REAL_PI / R(180);
    real cx, sx, cy, sy, cz, sz;
    dmath_sincosr(deg.x * k, &sx, &cx);
    dmath_sincosr(deg.y * k, &sy, &cy);
    dmath_sincosr(deg.z * k, &sz, &cz);
    /* Rz * Ry * Rx */
    mat3 m;
    m.r[0] = v3(cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx);
    m.r[1] = v3(sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx);
    m.r[2] = v3(-sy, cy * sx, cy * cx);
    return m;
}
