/* log.h - one line of diagnostics on stderr, prefixed with the program's
 * name ("lanray-server: client 3 joined ..."), unless the program is quiet. */
#ifndef LANRAY_LOG_H
#define LANRAY_LOG_H

void log_line(int quiet, const char *prog, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
