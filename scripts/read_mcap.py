#!/usr/bin/env python3
"""Decodes every message of an MCAP log with the official readers.

    pip install mcap mcap-protobuf-support
    python3 scripts/read_mcap.py paper-flip.mcap

Prints the message count per topic and the last /errors message, and exits 1
unless every message decoded and the count equals the file's statistics.
"""
import collections
import sys

from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory


def main(path):
    counts = collections.Counter()
    last = None
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        stats = reader.get_summary().statistics
        for _schema, channel, message, decoded in reader.iter_decoded_messages():
            counts[channel.topic] += 1
            if channel.topic == "/errors":
                last = (message.log_time * 1e-9, decoded.psi, decoded.ex)
        meta = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
    for topic, n in sorted(counts.items()):
        print(f"{topic}: {n}")
    total = sum(counts.values())
    print(f"{total} messages decoded (statistics: {stats.message_count}); last /errors t, psi, ex = {last}")
    if meta:
        print("metadata:", meta)
    if total != stats.message_count:
        sys.exit(1)


if __name__ == "__main__":
    main(sys.argv[1])
