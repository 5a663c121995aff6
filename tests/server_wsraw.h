/* A small blocking WebSocket and HTTP client over a raw TCP socket, for the loopback
 * server tests (RFC 6455: client frames masked, server frames not). Raw, so a test can
 * send exactly the bad input it means (binary garbage, oversized text) and can stop
 * reading to play a slow consumer. Header-only; every call has a timeout. */
#ifndef GALE_SERVER_WSRAW_H
#define GALE_SERVER_WSRAW_H

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

typedef struct wsraw {
    int fd;
    uint8_t *buf;   /* owned: received bytes not yet parsed */
    size_t len, cap;
    int close_code; /* from the server's close frame, 0 before */
    char close_reason[128];
} wsraw;

/* Opens a TCP connection to 127.0.0.1:port; rcvbuf > 0 shrinks the receive buffer
 * (before connect, so the window is small from the start). -1 on failure. */
static inline int wsraw_tcp(int port, int rcvbuf)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) {
        return -1;
    }
    if (rcvbuf > 0) {
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    }
    struct sockaddr_in a = { .sin_family = AF_INET, .sin_port = htons((uint16_t)port) };
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

/* Reads at least one more byte into c->buf within timeout_ms; 0 ok, -1 closed/timeout. */
static inline int wsraw_fill(wsraw *c, int timeout_ms)
{
    struct pollfd p = { .fd = c->fd, .events = POLLIN };
    if (poll(&p, 1, timeout_ms) <= 0) {
        return -1;
    }
    if (c->cap - c->len < 65536) {
        size_t ncap = c->cap ? c->cap * 2 : 1 << 17;
        uint8_t *nb = realloc(c->buf, ncap);
        if (!nb) {
            return -1;
        }
        c->buf = nb;
        c->cap = ncap;
    }
    ssize_t n = recv(c->fd, c->buf + c->len, c->cap - c->len, 0);
    if (n <= 0) {
        return -1;
    }
    c->len += (size_t)n;
    return 0;
}

static inline int wsraw_send_all(int fd, const void *b, size_t n)
{
    const uint8_t *p = b;
    while (n) {
        ssize_t k = send(fd, p, n, MSG_NOSIGNAL);
        if (k <= 0) {
            return -1;
        }
        p += k;
        n -= (size_t)k;
    }
    return 0;
}

/* Connects and upgrades to WebSocket with subprotocol "gale". 0 ok. */
static inline int wsraw_open(wsraw *c, int port, int rcvbuf)
{
    memset(c, 0, sizeof *c);
    c->fd = wsraw_tcp(port, rcvbuf);
    if (c->fd < 0) {
        return -1;
    }
    char req[512];
    int n = snprintf(req, sizeof req,
                     "GET / HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nUpgrade: websocket\r\n"
                     "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                     "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: gale\r\n\r\n",
                     port);
    if (wsraw_send_all(c->fd, req, (size_t)n)) {
        return -1;
    }
    for (;;) {
        for (size_t i = 3; i < c->len; i++) {
            if (!memcmp(c->buf + i - 3, "\r\n\r\n", 4)) {
                int ok = c->len >= 12 && !memcmp(c->buf, "HTTP/1.1 101", 12);
                memmove(c->buf, c->buf + i + 1, c->len - i - 1);
                c->len -= i + 1;
                return ok ? 0 : -1;
            }
        }
        if (wsraw_fill(c, 3000)) {
            return -1;
        }
    }
}

/* Sends one masked frame of the given opcode (1 text, 2 binary, 8 close). */
static inline int wsraw_send(wsraw *c, int opcode, const void *data, size_t len)
{
    uint8_t h[14];
    size_t hl = 0;
    h[hl++] = (uint8_t)(0x80 | opcode);
    if (len < 126) {
        h[hl++] = (uint8_t)(0x80 | len);
    } else if (len < 65536) {
        h[hl++] = 0x80 | 126;
        h[hl++] = (uint8_t)(len >> 8);
        h[hl++] = (uint8_t)len;
    } else {
        h[hl++] = 0x80 | 127;
        for (int i = 7; i >= 0; i--) {
            h[hl++] = (uint8_t)((uint64_t)len >> (8 * i));
        }
    }
    const uint8_t mask[4] = { 0x12, 0x34, 0x56, 0x78 };
    memcpy(h + hl, mask, 4);
    hl += 4;
    uint8_t *m = malloc(len ? len : 1);
    if (!m) {
        return -1;
    }
    for (size_t i = 0; i < len; i++) {
        m[i] = ((const uint8_t *)data)[i] ^ mask[i & 3];
    }
    int rc = wsraw_send_all(c->fd, h, hl) || wsraw_send_all(c->fd, m, len);
    free(m);
    return rc ? -1 : 0;
}

static inline int wsraw_text(wsraw *c, const char *s)
{
    return wsraw_send(c, 1, s, strlen(s));
}

/* Receives one whole message (continuations joined) into a malloc'd *out (NUL appended);
 * returns its opcode (1 text, 2 binary), 8 after a close frame (close_code filled), or -1
 * on timeout / connection end. Pings are answered by nothing (the server sends none). */
static inline int wsraw_recv(wsraw *c, uint8_t **out, size_t *out_len, int timeout_ms)
{
    uint8_t *msg = NULL;
    size_t mlen = 0;
    int op = -1;
    *out = NULL;
    *out_len = 0;
    for (;;) {
        if (c->len >= 2) {
            size_t need = 2, plen = c->buf[1] & 0x7f;
            if (plen == 126) {
                need = 4;
            } else if (plen == 127) {
                need = 10;
            }
            if (c->len >= need) {
                if (plen == 126) {
                    plen = (size_t)c->buf[2] << 8 | c->buf[3];
                } else if (plen == 127) {
                    plen = 0;
                    for (int i = 0; i < 8; i++) {
                        plen = plen << 8 | c->buf[2 + i];
                    }
                }
                if (c->len >= need + plen) {
                    int fin = c->buf[0] & 0x80, code = c->buf[0] & 0x0f;
                    if (code) {
                        op = code;
                    }
                    uint8_t *nm = realloc(msg, mlen + plen + 1);
                    if (!nm) {
                        free(msg);
                        return -1;
                    }
                    msg = nm;
                    memcpy(msg + mlen, c->buf + need, plen);
                    mlen += plen;
                    msg[mlen] = 0;
                    memmove(c->buf, c->buf + need + plen, c->len - need - plen);
                    c->len -= need + plen;
                    if (op == 8) {
                        c->close_code = mlen >= 2 ? (msg[0] << 8 | msg[1]) : 1005;
                        snprintf(c->close_reason, sizeof c->close_reason, "%.*s",
                                 mlen > 2 ? (int)(mlen - 2) : 0, (const char *)msg + 2);
                    }
                    if (fin) {
                        *out = msg;
                        *out_len = mlen;
                        return op;
                    }
                    continue;
                }
            }
        }
        if (wsraw_fill(c, timeout_ms)) {
            free(msg);
            return -1;
        }
    }
}

/* Reads until a close frame arrives (or timeout / end); returns the close code, 0 if none. */
static inline int wsraw_wait_close(wsraw *c, int timeout_ms)
{
    for (;;) {
        uint8_t *m;
        size_t n;
        int op = wsraw_recv(c, &m, &n, timeout_ms);
        free(m);
        if (op == 8) {
            return c->close_code;
        }
        if (op < 0) {
            return c->close_code;
        }
    }
}

static inline void wsraw_close(wsraw *c)
{
    if (c->fd >= 0) {
        close(c->fd);
    }
    free(c->buf);
    memset(c, 0, sizeof *c);
    c->fd = -1;
}

/* HTTP GET path; returns the status code and a malloc'd body (caller frees), -1 on error. */
static inline int wsraw_http_get(int port, const char *path, char **body)
{
    *body = NULL;
    int fd = wsraw_tcp(port, 0);
    if (fd < 0) {
        return -1;
    }
    char req[256];
    int n = snprintf(req, sizeof req,
                     "GET %s HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n", path);
    wsraw c = { .fd = fd };
    if (wsraw_send_all(fd, req, (size_t)n)) {
        close(fd);
        return -1;
    }
    while (wsraw_fill(&c, 3000) == 0) {
    }
    close(fd);
    int status = -1;
    if (c.len > 12 && sscanf((const char *)c.buf, "HTTP/1.1 %d", &status) == 1) {
        for (size_t i = 3; i < c.len; i++) {
            if (!memcmp(c.buf + i - 3, "\r\n\r\n", 4)) {
                *body = malloc(c.len - i);
                if (*body) {
                    memcpy(*body, c.buf + i + 1, c.len - i - 1);
                    (*body)[c.len - i - 1] = 0;
                }
                break;
            }
        }
    }
    free(c.buf);
    return status;
}

#endif
