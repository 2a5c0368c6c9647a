#!/usr/bin/env python3
"""Decode a bag written by `whisker export --mcap` with the Python MCAP readers (`mcap`,
`mcap-ros2-support`: an independent CDR decoder driven by the bag's own ros2msg schemas)
and compare every table and whisk file with the dataset's CSV files; then, when `rosbags`
is installed, deserialise every message again with its typestore (a second decoder, whose
.msg parser also checks the schemas' syntax).

    pip install mcap mcap-ros2-support rosbags
    python3 scripts/mcap-check.py FILE.mcap DATASET_DIR

Exits 1 on the first difference, naming the topic, the message and the field.
"""
import csv
import math
import os
import sys
from collections import defaultdict

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory


def number(text):
    return float(text)


def main():
    bag, dataset = sys.argv[1], sys.argv[2]
    rows = defaultdict(list)  # topic -> [(sequence, decoded)]
    channels = {}
    counts = defaultdict(int)
    with open(bag, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        library = reader.get_header().library
        for _schema, channel, message, decoded in reader.iter_decoded_messages():
            channels[channel.topic] = channel
            counts[channel.topic] += 1
            if "csv_path" in channel.metadata or "whisk_folder" in channel.metadata:
                rows[channel.topic].append((message.sequence, decoded))
    checked = 0
    for topic, messages in sorted(rows.items()):
        meta = channels[topic].metadata
        messages.sort(key=lambda m: m[0])
        if "csv_path" in meta:
            path = os.path.join(dataset, meta["csv_path"])
            with open(path, newline="") as f:
                table = list(csv.reader(f))
            header, body = table[0], table[1:]
            if len(body) != len(messages):
                sys.exit(f"{topic}: {len(messages)} messages, {path} has {len(body)} rows")
            fields = [s for s in channels[topic].metadata["csv_kinds"]]
            names = list(messages[0][1].__slots__)[1:] if messages else []
            for (seq, m), row in zip(messages, body):
                values = [getattr(m, n) for n in names]
                for col, (kind, text, value) in enumerate(zip(fields, row, values)):
                    same = (
                        value == text
                        if kind == "s"
                        else (value == number(text) or (math.isinf(value) and text in ("inf", "-inf")))
                    )
                    if not same:
                        sys.exit(f"{topic}: message {seq}: column {header[col]}: {value!r} != {text!r}")
                checked += 1
        else:
            folder = meta["whisk_folder"]
            n = int(meta["samples_per_whisk"])
            current, table = None, None
            for seq, m in messages:
                if m.whisk != current:
                    current = m.whisk
                    with open(os.path.join(dataset, folder, f"whisk_{m.whisk:06d}.csv")) as f:
                        table = list(csv.reader(f))[1:]
                    if len(table) != n:
                        sys.exit(f"{folder}/whisk_{m.whisk:06d}.csv: {len(table)} rows")
                row = [int(v) for v in table[m.sample]]
                got = [v for w in range(len(m.angle)) for v in (m.angle[w], m.x[w], m.y[w], m.spare[w])]
                if got != row:
                    sys.exit(f"{topic}: message {seq}: whisk {m.whisk} sample {m.sample} differs")
                checked += 1
    print(f"{bag}: {sum(counts.values())} messages on {len(counts)} topics decoded "
          f"(written by {library}); {checked} rows and samples "
          f"equal to {dataset}")
    rosbags_check(bag)
    for topic in sorted(counts):
        print(f"  {topic:45s} {channels[topic].schema_id:3d} {counts[topic]:8d}")


def rosbags_check(bag):
    try:
        from rosbags.typesys import Stores, get_typestore, get_types_from_msg
    except ImportError:
        print("rosbags not installed: second decoder skipped")
        return
    store = get_typestore(Stores.ROS2_HUMBLE)
    separator = "=" * 80 + "\n"
    with open(bag, "rb") as f:
        reader = make_reader(f)
        types = {}
        for schema in reader.get_summary().schemas.values():
            parts = schema.data.decode().split(separator)
            types.update(get_types_from_msg(parts[0], schema.name))
            for dependency in parts[1:]:
                name, body = dependency.split("\n", 1)
                package, short = name.removeprefix("MSG: ").split("/")
                types.update(get_types_from_msg(body, f"{package}/msg/{short}"))
        store.register(types)
        n = 0
        for schema, _channel, message in reader.iter_messages():
            store.deserialize_cdr(message.data, schema.name)
            n += 1
    print(f"rosbags deserialised all {n} messages")


if __name__ == "__main__":
    main()
