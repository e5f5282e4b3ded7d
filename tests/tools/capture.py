#!/usr/bin/env python3
"""Records a real lanray session, for the packet fuzzers' seed corpus.

    capture.py LISTEN_PORT SERVER_PORT TO_SERVER_FILE TO_CLIENT_FILE

Accepts one connection on 127.0.0.1:LISTEN_PORT, connects it to the server
on 127.0.0.1:SERVER_PORT and copies bytes both ways until both sides close,
writing each direction to its file with a leading mode byte 0 (the fuzz
harnesses' "whole stream from its first byte")."""
import select, socket, sys

listen_port, server_port = int(sys.argv[1]), int(sys.argv[2])
ls = socket.socket()
ls.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
ls.bind(("127.0.0.1", listen_port))
ls.listen(1)
client, _ = ls.accept()
server = socket.create_connection(("127.0.0.1", server_port))
logs = {client: bytearray(b"\0"), server: bytearray(b"\0")}  # bytes read from each side
peer = {client: server, server: client}
open_ = {client, server}
while open_:
    ready, _, _ = select.select(list(open_), [], [], 10)
    if not ready:
        break
    for s in ready:
        try:
            data = s.recv(65536)
        except ConnectionResetError:  # a side that closed with bytes unread (a server done with its frames)
            data = b""
        if not data:
            open_.discard(s)
            try:
                peer[s].shutdown(socket.SHUT_WR)
            except OSError:
                pass
            continue
        logs[s] += data
        peer[s].sendall(data)
with open(sys.argv[3], "wb") as f:
    f.write(logs[client])
with open(sys.argv[4], "wb") as f:
    f.write(logs[server])
