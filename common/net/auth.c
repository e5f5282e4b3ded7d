/* auth.c - see auth.h. */
#include "net/auth.h"

#include <sodium.h>
#include <stdlib.h>
#include <string.h>

static void token_key(const char *token, uint8_t key[crypto_auth_hmacsha256_KEYBYTES])
{
    crypto_hash_sha256(key, (const unsigned char *)token, strlen(token));
}

void auth_proof(const char *token, const uint8_t sn[PROTO_NONCE], const uint8_t cn[PROTO_NONCE], uint8_t proof[PROTO_PROOF])
{
    static const char label[] = "lanray-auth-v1";
    uint8_t key[crypto_auth_hmacsha256_KEYBYTES], msg[sizeof label - 1 + 2 * PROTO_NONCE];
    token_key(token ? token : "", key);
    memcpy(msg, label, sizeof label - 1);
    memcpy(msg + sizeof label - 1, sn, PROTO_NONCE);
    memcpy(msg + sizeof label - 1 + PROTO_NONCE, cn, PROTO_NONCE);
    crypto_auth_hmacsha256(proof, msg, sizeof msg, key);
    sodium_memzero(key, sizeof key);
}

int auth_proof_ok(const char *token, const uint8_t sn[PROTO_NONCE], const uint8_t cn[PROTO_NONCE], const uint8_t proof[PROTO_PROOF])
{
    uint8_t want[PROTO_PROOF];
    auth_proof(token, sn, cn, want);
    return sodium_memcmp(want, proof, PROTO_PROOF) == 0;
}

void auth_random(void *buf, size_t len)
{
    if (sodium_init() < 0)
        abort(); /* no entropy source: nothing secure can be done */
    randombytes_buf(buf, len);
}

void auth_hash(const void *data, size_t len, uint8_t hash[PROTO_HASH]) { crypto_hash_sha256(hash, data, len); }
