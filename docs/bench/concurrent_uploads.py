# Six concurrent 200 MB LoadScene uploads against one gistreamd; prints each
# status and the server's peak RSS (VmHWM).
import os, sys, threading
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../build/python"))
from gistream import client as gc
addr, pid, n, mb = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
blob = b"glTF" + b"\x02\x00\x00\x00" + b"\x00" * (mb * 1024 * 1024 - 8)
results = []
def one(i):
    c = gc.Client(addr, timeout=300)
    try:
        c.load_scene(gltf=blob)
        results.append((i, "OK"))
    except Exception as e:
        results.append((i, str(getattr(e, "code", lambda: "")()) + " " + (getattr(e, "details", lambda: str(e))() or "")[:150]))
ts = [threading.Thread(target=one, args=(i,)) for i in range(n)]
for t in ts: t.start()
for t in ts: t.join()
for r in sorted(results): print(r)
for line in open(f"/proc/{pid}/status"):
    if line.startswith(("VmHWM", "VmRSS")): print(line.strip())
