/* err.h: error messages passed up from library code, which never prints. */
#ifndef DRAPE_ERR_H
#define DRAPE_ERR_H

struct drape_err {
	char msg[512];
};

void err_set(struct drape_err *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
