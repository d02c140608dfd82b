/* term.c - text from a file made safe to print on a terminal (see term.h). */
#include "base/term.h"

#include <stdint.h>
#include <string.h>

/* The length of the valid UTF-8 sequence at s (1..4) with its code point in *cp, or 0
 * when s does not start one (a stray continuation byte, an overlong form, a surrogate,
 * a code point past U+10FFFF, a sequence cut short). */
static size_t utf8_decode(const unsigned char *s, uint32_t *cp)
{
    static const uint32_t least[5] = {0, 0, 0x80, 0x800, 0x10000};
    size_t n = s[0] >= 0xF0 ? 4 : s[0] >= 0xE0 ? 3 : s[0] >= 0xC0 ? 2 : 0;
    if (n == 0 || s[0] > 0xF4)
        return 0;
    uint32_t c = s[0] & (0x7F >> n);
    for (size_t i = 1; i < n; i++) {
        if ((s[i] & 0xC0) != 0x80)
            return 0;
        c = c << 6 | (s[i] & 0x3F);
    }
    if (c < least[n] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF))
        return 0;
    *cp = c;
    return n;
}

/* 1 for the code points a terminal or a bidirectional display obeys. */
static int steers(uint32_t c)
{
    return (c >= 0x80 && c <= 0x9F) || c == 0x061C || c == 0x200E || c == 0x200F ||
           (c >= 0x202A && c <= 0x202E) || (c >= 0x2066 && c <= 0x2069);
}

/* The next piece of s (one byte or one character) as it prints, into out (at most 8
 * bytes with the NUL); returns how many bytes of s it took. */
static size_t next_piece(const unsigned char *s, char out[8])
{
    static const char hex[] = "0123456789ABCDEF";
    unsigned char b = s[0];
    if (b >= 0x20 && b < 0x7F) {
        out[0] = (char)b;
        out[1] = '\0';
        return 1;
    }
    if (b < 0x80) {
        const char *named = b == '\n' ? "\\n" : b == '\r' ? "\\r" : b == '\t' ? "\\t" : NULL;
        if (named) {
            memcpy(out, named, 3);
        } else {
            memcpy(out, "\\x", 2);
            out[2] = hex[b >> 4];
            out[3] = hex[b & 15];
            out[4] = '\0';
        }
        return 1;
    }
    uint32_t c = 0;
    size_t n = utf8_decode(s, &c);
    if (n == 0) {
        memcpy(out, "\\x", 2);
        out[2] = hex[b >> 4];
        out[3] = hex[b & 15];
        out[4] = '\0';
        return 1;
    }
    if (steers(c)) {
        memcpy(out, "\\u", 2);
        for (int i = 0; i < 4; i++)
            out[2 + i] = hex[(c >> (12 - 4 * i)) & 15];
        out[6] = '\0';
        return n;
    }
    memcpy(out, s, n);
    out[n] = '\0';
    return n;
}

const char *rf_term_escape(const char *s, char *buf, size_t size)
{
    const unsigned char *start = (const unsigned char *)(s ? s : "");
    size_t whole = 0;
    for (const unsigned char *p = start; *p;) {
        char piece[8];
        p += next_piece(p, piece);
        whole += strlen(piece);
    }
    /* all of it when it fits, else whole pieces and "..." */
    size_t room = whole < size ? size - 1 : size - 4, used = 0;
    for (const unsigned char *p = start; *p;) {
        char piece[8];
        size_t took = next_piece(p, piece), len = strlen(piece);
        if (used + len > room)
            break;
        memcpy(buf + used, piece, len);
        used += len;
        p += took;
    }
    memcpy(buf + used, whole < size ? "" : "...", whole < size ? 1 : 4);
    return buf;
}

void rf_term_fputs(const char *s, FILE *out)
{
    const unsigned char *p = (const unsigned char *)(s ? s : "");
    while (*p) {
        char piece[8];
        p += next_piece(p, piece);
        fputs(piece, out);
    }
}
