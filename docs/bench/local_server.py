"""A gistreamd of its own for the Python bench scripts: started on a free
loopback port, yielded as (address, pid) once it prints `listening on`,
terminated at the end."""
import contextlib
import os
import re
import subprocess
import sys
import tempfile
import time


@contextlib.contextmanager
def local_gistreamd(gistreamd="build/gistreamd", scenes="scenes"):
    with tempfile.TemporaryDirectory() as tmp:
        log = open(os.path.join(tmp, "d.log"), "w+")
        server = subprocess.Popen([gistreamd, "--listen", "127.0.0.1:0", "--scenes", scenes],
                                  stdout=log, stderr=subprocess.DEVNULL)
        try:
            address = None
            for _ in range(300):
                log.seek(0)
                m = re.search(r"^listening on (\S+)", log.read(), re.M)
                if m:
                    address = m.group(1)
                    break
                time.sleep(0.1)
            if address is None:
                sys.exit("gistreamd did not start")
            yield address, server.pid
        finally:
            server.terminate()
            server.wait(timeout=30)
