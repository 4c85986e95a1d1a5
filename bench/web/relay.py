#!/usr/bin/env python3
"""The floor of one process between wheeltecd and a subscriber (bench/web/web_bench.cjs): blocking reads
and writes only. Each client gets a connection of its own to wheeltecd; after its first line (the
subscribe request) only the daemon's side is relayed, until either side closes.

  relay.py LISTEN_SOCKET WHEELTECD_SOCKET
"""
import os
import socket
import sys


def serve(client: socket.socket, daemon_path: str) -> None:
    request = b""
    while not request.endswith(b"\n"):
        chunk = client.recv(4096)
        if not chunk:
            return
        request += chunk
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as daemon:
        daemon.connect(daemon_path)
        daemon.sendall(request)
        while True:
            data = daemon.recv(65536)
            if not data:
                return
            client.sendall(data)


def main() -> None:
    listen_path, daemon_path = sys.argv[1], sys.argv[2]
    if os.path.exists(listen_path):
        os.unlink(listen_path)
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as listener:
        listener.bind(listen_path)
        listener.listen(4)
        while True:
            client, _ = listener.accept()
            with client:
                try:
                    serve(client, daemon_path)
                except OSError:
                    pass  # the bench closed its subscriber


if __name__ == "__main__":
    main()
