"""How soon Ctrl-C stops a solve: SIGINT from a timer thread 0.5 s into a run on a Voronoi mesh
of n x n cells, the time until KeyboardInterrupt reaches the caller.

    python crates/vem-python/python/examples/interrupt_latency.py [n]   # default n = 100
"""

import os
import signal
import sys
import threading
import time

import vemcontact as vc

n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
scene = vc.from_dict({"body": [{
    "name": "a",
    "mesh": vc.generated("voronoi", [[0, 0], [1, 1]], n, 1),
    "material": vc.isotropic(1.0, 0.3),
    "dirichlet": [{"part": "bottom", "x": 0, "y": 0}],
    "traction": [{"part": "top", "value": [0, -1]}],
}]})
sent = []


def interrupt():
    sent.append(time.perf_counter())
    os.kill(os.getpid(), signal.SIGINT)


timer = threading.Timer(0.5, interrupt)
timer.start()
try:
    scene.solve()
    print("the run ended before the signal")
except KeyboardInterrupt:
    print(f"KeyboardInterrupt {1e3 * (time.perf_counter() - sent[0]):.1f} ms after SIGINT")
