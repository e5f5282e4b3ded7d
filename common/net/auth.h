/* auth.h - what the protocol needs from cryptography (libsodium): the
 * handshake's proof that a client knows the server's token, the nonces'
 * randomness, and the content hash that names an asset. */
#ifndef LANRAY_AUTH_H
#define LANRAY_AUTH_H

#include <stddef.h>
#include <stdint.h>

#include "net/msg.h"

/* The authentication proof: HMAC-SHA256 keyed with SHA-256(token) over
 * "lanray-auth-v1" || server nonce || client nonce.  The token never travels. */
void auth_proof(const char *token, const uint8_t server_nonce[PROTO_NONCE], const uint8_t client_nonce[PROTO_NONCE],
                uint8_t proof[PROTO_PROOF]);
int auth_proof_ok(const char *token, const uint8_t server_nonce[PROTO_NONCE], const uint8_t client_nonce[PROTO_NONCE],
                  const uint8_t proof[PROTO_PROOF]);
/* Random bytes from the system's source (nonces); aborts without one. */
void auth_random(void *buf, size_t len);
/* SHA-256 of data: an asset's name on the wire. */
void auth_hash(const void *data, size_t len, uint8_t hash[PROTO_HASH]);

#endif
