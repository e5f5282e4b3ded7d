#!/usr/bin/env bash
# libm-imports.sh BINARY... - fails (naming it) where a binary imports a
# function of the C library's libm whose result glibc may round otherwise
# on another CPU: glibc picks its variant of sinf, cosf, sincosf, expf,
# powf (and of the double sin, cos, tan, atan, log2) by the CPU, with FMA
# or without, and they were found to differ (docs/renderer.md, "Arithmetic
# the same on every machine"); base/dmath.h has lanray's own.  Allowed:
# exact operations, and functions without variants here or checked on
# every float (logf, log2f, tanf).  Prints how many imports it checked.
# (A machine without libm.so.6 or nm checks nothing and prints 0.)
exact="fabs fabsf copysign copysignf floor floorf ceil ceilf rint rintf lrint lrintf trunc truncf fmod fmodf"
exact="$exact remainder remainderf frexp frexpf ldexp ldexpf nextafter nextafterf fmax fmaxf fmin fminf sqrt sqrtf"
same="asinf acosf atanf atan2f atan2 asin log logf log2f tanf"
libm=""
for f in /lib/*/libm.so.6 /usr/lib/*/libm.so.6 /lib64/libm.so.6; do
    [ -e "$f" ] && { libm=$f; break; }
done
n=0
if [ -n "$libm" ] && command -v nm >/dev/null; then
    exports=$(nm -D --defined-only "$libm" | awk '{print $3}' | sed 's/@.*//' | sort -u)
    for b in "$@"; do
        for f in $(nm -D --undefined-only "$b" | awk '{print $2}' | sed 's/@.*//' | sort -u | comm -12 - <(echo "$exports")); do
            case " $exact $same " in
            *" $f "*) n=$((n + 1)) ;;
            *) echo "$b calls the C library's $f, whose last bit glibc may give otherwise on another CPU (base/dmath.h)"; exit 1 ;;
            esac
        done
    done
fi
echo "$n"
