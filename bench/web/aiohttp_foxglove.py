#!/usr/bin/python3
"""The live view's telemetry channel as a Python developer would bridge it with aiohttp (Debian's
python3-aiohttp, asyncio): the yardstick of wheeltec-web's 0x103 -> Foxglove message latency in
bench/web/web_bench.cjs. One connection to wheeltecd subscribed to telemetry; the Foxglove WebSocket
protocol (foxglove.websocket.v1) on / with one channel, /wheeltec/telemetry, advertised as wheeltec-web
advertises it. Each notification is parsed once and its params, re-serialized, go to every subscription
in a Message Data frame (op 0x01, subscription id u32 LE, the record's time in ns u64 LE, payload).

  aiohttp_foxglove.py PORT WHEELTECD_SOCKET
"""
import asyncio
import itertools
import json
import struct
import sys

from aiohttp import WSMsgType, web

SUBPROTOCOL = "foxglove.websocket.v1"
CHANNEL_ID = 1


def number_object(*keys):
    return {"type": "object", "properties": {key: {"type": "number"} for key in keys}, "required": list(keys)}


# web/foxglove.cpp's telemetry_schema(), in its order of keys.
TELEMETRY_SCHEMA = json.dumps({
    "title": "wheeltec.Telemetry",
    "type": "object",
    "properties": {
        "seq": {"type": "integer"},
        "time": {"type": "number"},
        "stopped": {"type": "boolean"},
        "velocity": number_object("vx", "vy", "wz"),
        "accel": number_object("x", "y", "z"),
        "gyro": number_object("x", "y", "z"),
        "battery": {"type": "object", "properties": {"voltage": {"type": "number"}, "low": {"type": "boolean"}}},
        "odom": number_object("x", "y", "yaw"),
        "orientation": number_object("w", "x", "y", "z", "roll", "pitch", "yaw"),
    },
    "required": ["seq", "time", "velocity", "accel", "gyro", "battery", "odom"],
}, separators=(",", ":"))

ADVERTISE = json.dumps({"op": "advertise", "channels": [{
    "id": CHANNEL_ID, "topic": "/wheeltec/telemetry", "encoding": "json", "schemaName": "wheeltec.Telemetry",
    "schema": TELEMETRY_SCHEMA, "schemaEncoding": "jsonschema"}]})

HEADER = struct.Struct("<BIQ")  # opcode 0x01, subscription id, timestamp (ns)


class Client:
    def __init__(self, ws: web.WebSocketResponse):
        self.ws = ws
        self.subscriptions: dict[int, int] = {}  # subscription id -> channel id


class Bridge:
    def __init__(self):
        self.clients: set[Client] = set()
        self.sessions = itertools.count(1)

    async def handle(self, request: web.Request) -> web.WebSocketResponse:
        # Uncompressed, as wheeltec-web sends (aiohttp would otherwise accept permessage-deflate).
        ws = web.WebSocketResponse(protocols=(SUBPROTOCOL,), compress=False)
        await ws.prepare(request)
        client = Client(ws)
        await ws.send_str(json.dumps({"op": "serverInfo", "name": "aiohttp-foxglove", "capabilities": [],
                                      "supportedEncodings": ["json"], "metadata": {},
                                      "sessionId": str(next(self.sessions))}))
        await ws.send_str(ADVERTISE)
        self.clients.add(client)
        try:
            async for message in ws:
                if message.type != WSMsgType.TEXT:
                    continue
                try:
                    request_json = json.loads(message.data)
                    op = request_json.get("op")
                    if op == "subscribe":
                        for entry in request_json["subscriptions"]:
                            if entry["channelId"] == CHANNEL_ID:
                                client.subscriptions[int(entry["id"])] = CHANNEL_ID
                    elif op == "unsubscribe":
                        for subscription in request_json["subscriptionIds"]:
                            client.subscriptions.pop(subscription, None)
                except (ValueError, KeyError, TypeError, AttributeError) as error:
                    await ws.send_str(json.dumps({"op": "status", "level": 2, "message": f"malformed message: {error}"}))
        finally:
            self.clients.discard(client)
        return ws

    async def broadcast(self, timestamp_ns: int, payload: bytes) -> None:
        for client in list(self.clients):
            for subscription in list(client.subscriptions):
                try:
                    await client.ws.send_bytes(HEADER.pack(1, subscription, timestamp_ns) + payload)
                except ConnectionError:
                    self.clients.discard(client)
                    break

    async def relay_telemetry(self, reader: asyncio.StreamReader) -> None:
        while line := await reader.readline():
            message = json.loads(line)
            if message.get("method") != "telemetry":
                continue  # the subscribe request's result
            record = message["params"]
            payload = json.dumps(record, separators=(",", ":")).encode()
            await self.broadcast(round(record["time"] * 1e9), payload)
        raise SystemExit("aiohttp_foxglove.py: wheeltecd closed the connection")


async def main() -> None:
    port, daemon_path = int(sys.argv[1]), sys.argv[2]
    bridge = Bridge()
    # Subscribed before it listens: a client that connects is served from the next record on.
    reader, writer = await asyncio.open_unix_connection(daemon_path)
    writer.write(b'{"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["telemetry"]}}\n')
    await writer.drain()
    app = web.Application()
    app.router.add_get("/", bridge.handle)
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    await web.TCPSite(runner, "127.0.0.1", port).start()
    try:
        await bridge.relay_telemetry(reader)
    finally:
        await runner.cleanup()


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    asyncio.run(main())
