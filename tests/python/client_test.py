"""The Python client package against a real gistreamd on loopback
(llvmpipe without a GPU): load a scene, list solvers, render a PNG, run a
session whose frames echo the updates, set a material's metallic and
roughness (material_change), see a bad parameter come back as
INVALID_ARGUMENT naming it; over TLS with a bearer token (and
UNAUTHENTICATED without one). Run by ctest (python_client) with PYTHONPATH
set to build/python and GISTREAMD/GISTREAM_SCENES pointing at the binary
and the scene folder."""

import contextlib
import csv
import json
import os
import re
import subprocess
import tempfile
import unittest

from google.protobuf import json_format

import grpc

import gistream


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = subprocess.Popen(
            [os.environ["GISTREAMD"], "--listen", "127.0.0.1:0", "--scenes",
             os.environ["GISTREAM_SCENES"]],
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        line = cls.server.stdout.readline()  # "listening on ADDR" once it serves
        if not line.startswith("listening on "):
            cls.server.kill()
            raise RuntimeError(f"gistreamd did not start: {line!r}")
        cls.client = gistream.Client(line.split()[-1], timeout=120)
        cls.scene = cls.client.load_scene("cornell_box")

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.terminate()
        cls.server.wait(timeout=30)

    def test_scene_and_solvers(self):
        self.assertTrue(self.scene.scene_id)
        self.assertGreater(self.scene.triangle_count, 0)
        names = [s.name for s in self.client.solvers()]
        for solver in ("direct", "pathtrace", "sh_probes", "avg", "implicit_visibility",
                       "antiradiance"):
            self.assertIn(solver, names)

    def test_render_writes_a_png(self):
        frame = self.client.render(self.scene.scene_id, params={"area_samples": 4},
                                   size=(32, 24), format="png")
        self.assertEqual(frame.image[:8], b"\x89PNG\r\n\x1a\n")
        self.assertEqual((frame.width, frame.height), (32, 24))
        self.assertEqual(frame.solver, "direct")
        self.assertIn("shade", [t.name for t in frame.timings])

    def test_session_frames_echo_the_updates(self):
        with self.client.session(self.scene.scene_id, params={"area_samples": 4},
                                 size=(32, 24), fps=60) as session:
            self.assertTrue(session.opened.session_id)
            seq = session.update(camera=gistream.look_at((0.9, 0.3, 0.3), (0.28, 0.27, 0.28)))
            self.assertEqual(seq, 1)
            for frame in session.frames(50, stop_at_rest=False):
                if frame.last_update_seq >= seq:
                    break
            self.assertEqual(frame.last_update_seq, seq)
            self.assertFalse(session.rejected)

    def test_frames_of_a_still_view_end_at_rest(self):
        # A still direct view refines over 4 frames (refine_samples) and
        # then settles; its first keep-alive says at_rest, and frames() ends
        # there instead of waiting for 100 keep-alives a second apart.
        with self.client.session(self.scene.scene_id, params={"area_samples": 4},
                                 size=(32, 24), fps=60, refine_samples=4) as session:
            frames = list(session.frames(100))
            self.assertLess(len(frames), 100)
            self.assertEqual(frames[-1].stats["at_rest"], 1.0)
            self.assertTrue(frames[-1].unchanged)
            last = gistream.convergence(frames[-1])
            self.assertEqual(last["refine_samples"], 4.0)
            self.assertEqual(last["refine_target"], 4.0)
            self.assertEqual(last["update_complete"], 1.0)
            self.assertEqual(gistream.convergence(frames[0])["refine_samples"], 1.0)

    def test_material_change_sets_metallic_and_roughness(self):
        # glossy_box, which no other test here loads (a named scene is shared
        # by one client's loads): material 0 is its grey Lambertian walls.
        scene = self.client.load_scene("glossy_box")
        try:
            change = gistream.material_change(0, metallic=1.0, roughness=0.25)
            self.assertTrue(change.HasField("metallic") and change.HasField("roughness"))
            self.assertEqual((change.metallic, change.roughness), (1.0, 0.25))
            self.assertFalse(change.HasField("emissive_strength"))
            with self.assertRaisesRegex(ValueError, "roughness: 1.5 is outside"):
                gistream.material_change(0, roughness=1.5)
            before = self.client.render(scene.scene_id, params={"area_samples": 4},
                                        size=(32, 24), format="png")
            after = self.client.render(scene.scene_id, params={"area_samples": 4},
                                       size=(32, 24), format="png",
                                       updates=[gistream.pb.Update(seq=1, material=change)])
            self.assertNotEqual(before.image, after.image)  # `direct` shades GGX
            self.assertEqual(after.last_update_seq, 1)
            # The server checks the range too and names the field.
            bad = gistream.pb.Update(seq=2, material=gistream.pb.MaterialChange(
                material=0, roughness=2.0))
            with self.assertRaises(grpc.RpcError) as caught:
                self.client.render(scene.scene_id, size=(8, 8), updates=[bad])
            self.assertEqual(caught.exception.code(), grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIn("roughness", caught.exception.details())
        finally:
            self.client.unload_scene(scene.scene_id)

    def test_a_bad_parameter_names_itself(self):
        with self.assertRaises(grpc.RpcError) as caught:
            self.client.render(self.scene.scene_id, params={"area_samples": 0}, size=(8, 8))
        self.assertEqual(caught.exception.code(), grpc.StatusCode.INVALID_ARGUMENT)
        self.assertIn("area_samples", caught.exception.details())


if __name__ == "__main__":
    unittest.main()


class BenchReferencesTest(unittest.TestCase):
    """`gistream bench --reference-spp` (issue 27): frames.csv has a row per
    frame of the first session, each against references/step1_seq<n>.exr,
    the path-traced reference of the state that frame shows (every update
    sent up to seq n, in its .json); that file equals a fresh render of
    that state reached another way."""

    def bench(self, address, workload, spp):
        out = tempfile.mkdtemp(prefix="gistream_bench_refs_")
        run = subprocess.run(
            [os.environ["GISTREAM"], "--server", address, "bench", "--sessions", "1",
             "--duration", "2s", "--warmup", "0s", "--size", "16x16", "--format", "exr",
             "--workload", workload, "--update-hz", "5", "--reference-spp", str(spp),
             "--param", "area_samples=4", "--out", out],
            capture_output=True, text=True, timeout=240)
        self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
        with open(os.path.join(out, "frames.csv")) as f:
            rows = list(csv.DictReader(f))
        seqs = sorted({int(r["seq"]) for r in rows})
        # Under load (ctest -j) a few frames, at least one showing an update.
        self.assertGreaterEqual(seqs[-1], 1, rows)
        refs = os.path.join(out, "references")
        for seq in seqs:
            self.assertTrue(os.path.isfile(os.path.join(refs, f"step1_seq{seq}.exr")), seq)
            with open(os.path.join(refs, f"step1_seq{seq}.json")) as f:
                updates = [json_format.ParseDict(u, gistream.pb.Update()) for u in json.load(f)]
            # The state of seq n: every update up to n, in order (none for
            # a frame before the first update).
            self.assertEqual([u.seq for u in updates], list(range(1, seq + 1)))
        last = seqs[-1]
        with open(os.path.join(refs, f"step1_seq{last}.json")) as f:
            updates = [json_format.ParseDict(u, gistream.pb.Update()) for u in json.load(f)]
        with open(os.path.join(refs, f"step1_seq{last}.exr"), "rb") as f:
            reference = f.read()
        print(f"{workload}: frames.csv: {len(rows)} rows over seqs {seqs}")
        return updates, reference

    def assert_same_exr(self, fresh, reference):
        # The same path tracer, samples and seed on the same state: the
        # same file, but for the capture date OpenImageIO writes into the
        # EXR header.
        undated = lambda exr: re.sub(rb"capDate\x00string\x00\x13\x00\x00\x00.{19}", b"",
                                     exr, count=1, flags=re.S)
        self.assertNotEqual(undated(reference), reference)
        self.assertEqual(undated(fresh), undated(reference))

    def test_references_match_a_fresh_render(self):
        """The object workload: the updates sent through a session on a
        fresh private copy, then a Render without updates (the bench sends
        them inside the Render)."""
        with local_server() as address:
            updates, reference = self.bench(address, "object", 8)
            with gistream.Client(address, timeout=120) as client:
                copy = client.stub.LoadScene(
                    gistream.pb.LoadSceneRequest(name="cornell_box", private_copy=True),
                    timeout=120)
                with client.session(copy.scene_id, size=(16, 16), fps=60) as session:
                    for u in updates:
                        kind = u.WhichOneof("change")
                        seq = session.update(**{{"node_transform": "node"}.get(kind, kind):
                                                getattr(u, kind)})
                    for frame in session.frames(100, stop_at_rest=False):
                        if frame.last_update_seq >= seq:
                            break
                fresh = client.render(copy.scene_id, solver="pathtrace",
                                      params={"spp": 8, "seed": 1}, size=(16, 16), format="exr")
            self.assert_same_exr(fresh.image, reference)

    def test_orbit_references_keep_the_camera_over_every_chunk(self):
        """The orbit workload: a camera's change is a session's, so each of
        a reference's progressive calls (128 spp: two of 64) must carry the
        state's camera; the reference equals two 64-spp Renders on a fresh
        copy with that camera."""
        with local_server() as address:
            updates, reference = self.bench(address, "orbit", 128)
            camera = gistream.pb.CameraChange()
            for u in updates:
                self.assertEqual(u.WhichOneof("change"), "camera")
                camera.MergeFrom(u.camera)
            with gistream.Client(address, timeout=120) as client:
                copy = client.stub.LoadScene(
                    gistream.pb.LoadSceneRequest(name="cornell_box", private_copy=True),
                    timeout=120)
                for _ in range(2):
                    fresh = client.render(copy.scene_id, solver="pathtrace",
                                          params={"spp": 64, "seed": 1}, size=(16, 16),
                                          format="exr", camera=camera)
            self.assert_same_exr(fresh.image, reference)


@contextlib.contextmanager
def local_server():
    server = subprocess.Popen(
        [os.environ["GISTREAMD"], "--listen", "127.0.0.1:0", "--scenes",
         os.environ["GISTREAM_SCENES"]],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        yield server.stdout.readline().split()[-1]
    finally:
        server.terminate()
        server.wait(timeout=30)


class TlsTokenTest(unittest.TestCase):
    """gistreamd with TLS (certificates from scripts/dev_certs.sh) and a
    token file: the client's tls_credentials and token."""

    TOKEN = "python-test-token-0123456789"

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        source = os.path.dirname(os.path.abspath(os.environ["GISTREAM_SCENES"]))
        subprocess.run([os.path.join(source, "scripts", "dev_certs.sh"), cls.dir.name], check=True)
        tokens = os.path.join(cls.dir.name, "tokens")
        with open(tokens, "w") as f:
            f.write(f"{cls.TOKEN} python\n")
        tls = lambda name: os.path.join(cls.dir.name, name)
        cls.server = subprocess.Popen(
            [os.environ["GISTREAMD"], "--listen", "127.0.0.1:0", "--scenes",
             os.environ["GISTREAM_SCENES"], "--tls-cert", tls("server.crt"), "--tls-key",
             tls("server.key"), "--auth-tokens", tokens],
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        line = cls.server.stdout.readline()
        if not line.startswith("listening on "):
            cls.server.kill()
            raise RuntimeError(f"gistreamd did not start: {line!r}")
        cls.address = "localhost:" + line.split(":")[-1].strip()
        cls.credentials = gistream.tls_credentials(ca=tls("ca.crt"))

    @classmethod
    def tearDownClass(cls):
        cls.server.terminate()
        cls.server.wait(timeout=30)
        cls.dir.cleanup()

    def test_render_over_tls_with_a_token(self):
        with gistream.Client(self.address, timeout=120, credentials=self.credentials,
                             token=self.TOKEN) as client:
            scene = client.load_scene("cornell_box")
            frame = client.render(scene.scene_id, params={"area_samples": 4}, size=(16, 16),
                                  format="png")
            self.assertEqual(frame.image[:8], b"\x89PNG\r\n\x1a\n")

    def test_no_token_is_unauthenticated(self):
        env_token = os.environ.pop("GISTREAM_TOKEN", None)
        try:
            with gistream.Client(self.address, timeout=30, credentials=self.credentials) as client:
                with self.assertRaises(grpc.RpcError) as caught:
                    client.solvers()
                self.assertEqual(caught.exception.code(), grpc.StatusCode.UNAUTHENTICATED)
        finally:
            if env_token is not None:
                os.environ["GISTREAM_TOKEN"] = env_token
