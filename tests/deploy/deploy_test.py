"""The deployment files hold what the server needs (issue 15): the Helm
chart rendered by helm_render.py (helm is not in Debian 12) with its
defaults and with the switches set, the Kubernetes manifest generated from
it, the Compose file and the Dockerfile. Checked: the port wired to
gistreamd --listen, probes on the plaintext health port, TLS and token
secrets mounted where the flags read them, a non-root read-only pod without
capabilities, runtimeClassName and GPU tolerations, nvidia.com/gpu limits, a
scene volume, the metrics port and ServiceMonitor, a PodDisruptionBudget and
grace periods longer than the shutdown deadline.

    /usr/bin/python3 -m unittest -v deploy_test     (ctest: deploy_files)
"""

import os
import re
import unittest

import yaml

import helm_render

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CHART = os.path.join(ROOT, "deploy", "helm", "gistream")


def render(overrides=None, release="gistream"):
    """{kind: [documents]} of the chart rendered with `overrides`."""
    docs = {}
    for name, text in helm_render.render_chart(CHART, release, overrides).items():
        for doc in yaml.safe_load_all(text):
            if doc:
                docs.setdefault(doc["kind"], []).append(doc)
    return docs


def flag(args, name):
    """The value after `name` in a container's args (None when absent)."""
    return args[args.index(name) + 1] if name in args else None


def duration_s(text):
    m = re.fullmatch(r"(\d+)s", str(text))
    assert m, f"not a duration in seconds: {text!r}"
    return int(m.group(1))


class ChartTest(unittest.TestCase):
    def deployment(self, docs):
        self.assertEqual(len(docs["Deployment"]), 1)
        return docs["Deployment"][0]

    def check_server(self, docs, port, health_port, deadline_s):
        """What every rendering must hold."""
        pod = self.deployment(docs)["spec"]["template"]["spec"]
        (container,) = pod["containers"]
        args = [str(a) for a in container["args"]]
        self.assertEqual(flag(args, "--listen"), f"0.0.0.0:{port}")
        self.assertEqual(flag(args, "--health-listen"), f"0.0.0.0:{health_port}")
        ports = {p["name"]: p["containerPort"] for p in container["ports"]}
        self.assertEqual(ports["grpc"], port)
        self.assertEqual(ports["health"], health_port)
        for probe in ("startupProbe", "readinessProbe", "livenessProbe"):
            self.assertEqual(container[probe]["grpc"]["port"], health_port, probe)
        # TLS and tokens: the flags read the files the secrets put there.
        mounts = {m["name"]: m for m in container["volumeMounts"]}
        volumes = {v["name"]: v for v in pod["volumes"]}
        self.assertEqual(os.path.dirname(flag(args, "--tls-cert")), mounts["tls"]["mountPath"])
        self.assertEqual(os.path.dirname(flag(args, "--tls-key")), mounts["tls"]["mountPath"])
        self.assertEqual(os.path.dirname(flag(args, "--auth-tokens")),
                         mounts["tokens"]["mountPath"])
        self.assertEqual(os.path.basename(flag(args, "--tls-cert")), "tls.crt")  # kubernetes.io/tls
        self.assertEqual(os.path.basename(flag(args, "--auth-tokens")), "tokens")
        self.assertTrue(volumes["tls"]["secret"]["secretName"])
        self.assertTrue(volumes["tokens"]["secret"]["secretName"])
        self.assertTrue(all(m.get("readOnly") for n, m in mounts.items() if n != "tmp"))
        # Non-root, read-only, no capabilities, no escalation.
        self.assertTrue(pod["securityContext"]["runAsNonRoot"])
        self.assertNotEqual(pod["securityContext"]["runAsUser"], 0)
        sc = container["securityContext"]
        self.assertTrue(sc["readOnlyRootFilesystem"])
        self.assertFalse(sc["allowPrivilegeEscalation"])
        self.assertEqual(sc["capabilities"]["drop"], ["ALL"])
        # The grace period outlasts the shutdown deadline.
        self.assertEqual(float(flag(args, "--shutdown-deadline-s")), deadline_s)
        self.assertGreater(pod["terminationGracePeriodSeconds"], deadline_s)
        # The Service reaches the gRPC port; PDB and Service select the pods.
        labels = self.deployment(docs)["spec"]["template"]["metadata"]["labels"]
        (service,) = docs["Service"]
        self.assertEqual(service["spec"]["selector"], labels)
        self.assertIn({"name": "grpc", "port": port, "targetPort": "grpc"},
                      service["spec"]["ports"])
        (pdb,) = docs["PodDisruptionBudget"]
        self.assertEqual(pdb["spec"]["selector"]["matchLabels"], labels)
        return pod, container, args

    def test_defaults(self):
        docs = render()
        pod, container, args = self.check_server(docs, 50051, 50052, 10)
        self.assertEqual(pod["runtimeClassName"], "nvidia")
        self.assertIn({"key": "nvidia.com/gpu", "operator": "Exists", "effect": "NoSchedule"},
                      pod["tolerations"])
        self.assertEqual(container["resources"]["limits"]["nvidia.com/gpu"], 1)
        self.assertIsNone(flag(args, "--tls-client-ca"))
        self.assertIsNone(flag(args, "--metrics-listen"))
        self.assertNotIn("ServiceMonitor", docs)
        self.assertIsNone(flag(args, "--scenes"))  # the image's scenes

    def test_port_moves_listen_probes_and_service_together(self):
        docs = render({"port": 7000, "healthPort": 7001, "shutdownDeadlineSeconds": 45})
        self.check_server(docs, 7000, 7001, 45)

    def test_switches(self):
        docs = render({
            "gpusPerPod": 0, "runtimeClassName": "", "tls": {"mutualTls": True},
            "metrics": {"enabled": True, "serviceMonitor": True, "port": 9999},
            "scenes": {"volume": {"persistentVolumeClaim": {"claimName": "scenes"}}},
            "extraArgs": ["--max-sessions", "16"]})
        pod, container, args = self.check_server(docs, 50051, 50052, 10)
        self.assertNotIn("runtimeClassName", pod)
        self.assertNotIn("nvidia.com/gpu", container["resources"]["limits"])
        self.assertEqual(flag(args, "--tls-client-ca"), "/etc/gistream/tls/ca.crt")
        self.assertEqual(flag(args, "--max-sessions"), "16")
        # Metrics: flag, container port, Service port, ServiceMonitor on it.
        self.assertEqual(flag(args, "--metrics-listen"), "0.0.0.0:9999")
        self.assertIn({"name": "metrics", "containerPort": 9999}, container["ports"])
        (service,) = docs["Service"]
        self.assertIn({"name": "metrics", "port": 9999, "targetPort": "metrics"},
                      service["spec"]["ports"])
        (monitor,) = docs["ServiceMonitor"]
        self.assertEqual(monitor["spec"]["endpoints"][0]["port"], "metrics")
        self.assertEqual(monitor["spec"]["selector"]["matchLabels"], service["metadata"]["labels"])
        # The scene volume, read-only, is what --scenes names.
        mounts = {m["name"]: m for m in container["volumeMounts"]}
        self.assertEqual(flag(args, "--scenes"), mounts["scenes"]["mountPath"])
        volumes = {v["name"]: v for v in pod["volumes"]}
        self.assertEqual(volumes["scenes"]["persistentVolumeClaim"]["claimName"], "scenes")

    def test_admission_and_autoscaling_on_render_time(self):
        # Admission by GPU time is on by default; no HPA unless asked.
        docs = render()
        _, _, args = self.check_server(docs, 50051, 50052, 10)
        self.assertEqual(float(flag(args, "--max-render-busy")), 0.85)
        self.assertNotIn("HorizontalPodAutoscaler", docs)
        docs = render({"metrics": {"enabled": True},
                       "autoscaling": {"enabled": True, "maxReplicas": 5}})
        _, _, args = self.check_server(docs, 50051, 50052, 10)
        (hpa,) = docs["HorizontalPodAutoscaler"]
        spec = hpa["spec"]
        self.assertEqual(spec["scaleTargetRef"]["name"],
                         self.deployment(docs)["metadata"]["name"])
        self.assertEqual((spec["minReplicas"], spec["maxReplicas"]), (1, 5))
        (metric,) = spec["metrics"]
        self.assertEqual(metric["pods"]["metric"]["name"], "gistream_render_busy_ratio")
        # The target leaves room under the admission limit for new sessions.
        target = float(metric["pods"]["target"]["averageValue"])
        self.assertLess(target, float(flag(args, "--max-render-busy")))
        # Scale-down removes one pod at a time: each drains, as the PDB allows.
        (policy,) = spec["behavior"]["scaleDown"]["policies"]
        self.assertEqual((policy["type"], policy["value"]), ("Pods", 1))
        (pdb,) = docs["PodDisruptionBudget"]
        self.assertEqual(pdb["spec"]["maxUnavailable"], 1)
        # The metric the HPA reads is served.
        self.assertEqual(flag(args, "--metrics-listen"), "0.0.0.0:9464")

    def test_web_gateway(self):
        """gistream-web in the chart (web.enabled): TLS to the chart's
        gistreamd checked against its CA, its token from a Secret, a GI
        solver, bounded pages, probes on /healthz, metrics on their port."""
        self.assertNotIn("web", [d["metadata"]["name"].split("-")[-1]
                                 for d in render().get("Deployment", [])])
        docs = render({"web": {"enabled": True, "allowOrigins": ["https://viewer.example"]}})
        (web,) = [d for d in docs["Deployment"] if d["metadata"]["name"] == "gistream-web"]
        pod = web["spec"]["template"]["spec"]
        (container,) = pod["containers"]
        args = container["args"]
        self.assertEqual(container["command"], ["/usr/local/bin/gistream-web"])
        (gistreamd_service,) = [s for s in docs["Service"]
                                if s["metadata"]["name"] == "gistream-gistreamd"]
        host, port = flag(args, "--server").rsplit(":", 1)
        self.assertEqual((host, int(port)), (gistreamd_service["metadata"]["name"], 50051))
        self.assertEqual(flag(args, "--solver"), "antiradiance")
        self.assertNotIn("pathtrace", flag(args, "--solvers"))
        self.assertEqual(flag(args, "--page-params"), "none")
        self.assertEqual(flag(args, "--allow-origin"), "https://viewer.example")
        ports = {p["name"]: p["containerPort"] for p in container["ports"]}
        self.assertEqual(flag(args, "--listen"), f"0.0.0.0:{ports['http']}")
        self.assertEqual(flag(args, "--metrics-listen"), f"0.0.0.0:{ports['metrics']}")
        self.assertEqual(container["readinessProbe"]["httpGet"]["path"], "/healthz")
        (token,) = container["env"]
        self.assertEqual(token["name"], "GISTREAM_TOKEN")
        self.assertEqual(token["valueFrom"]["secretKeyRef"]["key"], "token")
        # The CA that checks gistreamd is the chart's TLS secret's.
        (tls,) = pod["volumes"]
        self.assertEqual(tls["secret"]["secretName"], "gistream-tls")
        (mount,) = container["volumeMounts"]
        self.assertEqual(flag(args, "--ca"), mount["mountPath"] + "/ca.crt")
        self.assertTrue(container["securityContext"]["readOnlyRootFilesystem"])
        self.assertTrue(pod["securityContext"]["runAsNonRoot"])
        (service,) = [s for s in docs["Service"] if s["metadata"]["name"] == "gistream-web"]
        self.assertEqual(service["spec"]["selector"], web["spec"]["selector"]["matchLabels"])
        self.assertEqual({p["targetPort"] for p in service["spec"]["ports"]}, set(ports))
        self.assertIsNone(flag(args, "--viewer-tokens"))
        # Viewer tokens from a Secret, where the flag reads them.
        docs = render({"web": {"enabled": True, "viewerTokensSecretName": "viewers"}})
        (web,) = [d for d in docs["Deployment"] if d["metadata"]["name"] == "gistream-web"]
        pod = web["spec"]["template"]["spec"]
        (container,) = pod["containers"]
        mounts = {m["name"]: m["mountPath"] for m in container["volumeMounts"]}
        volumes = {v["name"]: v for v in pod["volumes"]}
        self.assertEqual(volumes["viewers"]["secret"]["secretName"], "viewers")
        (item,) = volumes["viewers"]["secret"]["items"]
        self.assertEqual(flag(container["args"], "--viewer-tokens"),
                         mounts["viewers"] + "/" + item["path"])

    def test_metrics_without_service_monitor(self):
        docs = render({"metrics": {"enabled": True}})
        self.assertNotIn("ServiceMonitor", docs)

    def test_renderer_refuses_what_it_does_not_know(self):
        with self.assertRaises(helm_render.TemplateError):
            helm_render._Renderer({}, "r").render(
                helm_render._parse(helm_render._tokens("{{ include \"x\" . }}")))


class ManifestTest(unittest.TestCase):
    def test_k8s_manifest_is_the_rendered_chart(self):
        """deploy/k8s/gistream.yaml is generated from the chart (deploy/README.md):
        regenerate it when the chart changes."""
        with open(os.path.join(ROOT, "deploy", "k8s", "gistream.yaml")) as f:
            manifest = [d for d in yaml.safe_load_all(f) if d]
        rendered = [d for docs in render().values() for d in docs]
        key = lambda d: (d["kind"], d["metadata"]["name"])
        self.assertEqual(sorted(manifest, key=key), sorted(rendered, key=key))

    def test_balancer_reaches_the_chart_service_by_hash(self):
        """deploy/k8s/balancer.yaml runs deploy/haproxy/haproxy.cfg (the file
        the fleet test runs) unchanged, with TLS on both sides, against the
        chart's headless Service."""
        with open(os.path.join(ROOT, "deploy", "k8s", "balancer.yaml")) as f:
            docs = {d["kind"]: d for d in yaml.safe_load_all(f) if d}
        with open(os.path.join(ROOT, "deploy", "haproxy", "haproxy.cfg")) as f:
            tested = f.read()
        self.assertEqual(docs["ConfigMap"]["data"]["haproxy.cfg"], tested)
        self.assertIn("balance hdr(x-gistream-affinity)", tested)
        self.assertIn("hash-type consistent", tested)
        pod = docs["Deployment"]["spec"]["template"]["spec"]
        (container,) = pod["containers"]
        env = {e["name"]: e.get("value") for e in container["env"]}
        # Every variable the file reads is set: both TLS sides on.
        for name in set(re.findall(r"\$\{(\w+)\}", tested)):
            self.assertIn(name, env, name)
        (service,) = render()["Service"]
        host, port = env["GISTREAM_SERVERS"].rsplit(":", 1)
        self.assertEqual(host, service["metadata"]["name"] + ".$(POD_NAMESPACE).svc.cluster.local")
        self.assertEqual(service["spec"]["clusterIP"], "None")  # DNS lists every ready pod
        self.assertEqual(int(port), 50051)
        self.assertEqual(env["GISTREAM_UPSTREAM_NAME"], service["metadata"]["name"])
        self.assertEqual(int(env["GISTREAM_LB_BIND"].lstrip(":")),
                         container["ports"][0]["containerPort"])
        # Enough server slots for the autoscaler's largest fleet.
        slots = int(re.search(r"server-template \w+ (\d+)", tested).group(1))
        with open(os.path.join(ROOT, "deploy", "helm", "gistream", "values.yaml")) as f:
            self.assertGreaterEqual(slots, yaml.safe_load(f)["autoscaling"]["maxReplicas"])
        # The pods' CA comes from the chart's TLS secret; the key sits where
        # HAProxy looks for it ("<certificate>.key").
        volumes = {v["name"]: v for v in pod["volumes"]}
        self.assertEqual(volumes["upstream"]["secret"]["secretName"],
                         render()["Deployment"][0]["spec"]["template"]["spec"]["volumes"][0][
                             "secret"]["secretName"])
        mounts = {m["name"]: m["mountPath"] for m in container["volumeMounts"]}
        items = {i["key"]: i["path"] for i in volumes["tls"]["secret"]["items"]}
        self.assertEqual(env["GISTREAM_LB_CERT"], mounts["tls"] + "/" + items["tls.crt"])
        self.assertEqual(items["tls.key"], items["tls.crt"] + ".key")
        self.assertEqual(env["GISTREAM_UPSTREAM_CA"], mounts["upstream"] + "/ca.crt")
        self.assertIn("/etc/haproxy/config/haproxy.cfg", container["args"])
        self.assertEqual(mounts["config"], "/etc/haproxy/config")

    def test_compose(self):
        with open(os.path.join(ROOT, "deploy", "compose.yaml")) as f:
            service = yaml.safe_load(f)["services"]["gistreamd"]
        command = service["command"]
        deadline = float(flag(command, "--shutdown-deadline-s"))
        self.assertGreater(duration_s(service["stop_grace_period"]), deadline)
        self.assertEqual(flag(command, "--listen"), "0.0.0.0:50051")
        self.assertTrue(flag(command, "--tls-cert") and flag(command, "--auth-tokens"))
        self.assertTrue(0.0 < float(flag(command, "--max-render-busy")) <= 1.0)
        health = flag(command, "--health-listen").split(":")[-1]
        self.assertIn(f"127.0.0.1:{health}", service["healthcheck"]["test"])
        self.assertIn("health", service["healthcheck"]["test"])
        self.assertTrue(service["read_only"])
        self.assertEqual(service["cap_drop"], ["ALL"])

    def test_compose_runs_the_viewer_gateway_against_gistreamd(self):
        with open(os.path.join(ROOT, "deploy", "compose.yaml")) as f:
            services = yaml.safe_load(f)["services"]
        web, server = services["gistream-web"], services["gistreamd"]
        command = web["command"]
        # It reaches the server's service name on its --listen port, over TLS
        # with a token from its env file, once the server is healthy.
        port = flag(server["command"], "--listen").split(":")[-1]
        self.assertEqual(flag(command, "--server"), f"gistreamd:{port}")
        self.assertIn("--tls", command)
        self.assertTrue(flag(command, "--ca"))
        self.assertEqual(web["depends_on"]["gistreamd"]["condition"], "service_healthy")
        self.assertTrue(web["env_file"])
        self.assertEqual(web["image"], server["image"])
        # Served on the port it publishes; health from its /healthz.
        listen_port = flag(command, "--listen").split(":")[-1]
        self.assertIn(f"{listen_port}:{listen_port}", web["ports"])
        self.assertIn(f"/dev/tcp/127.0.0.1/{listen_port}", " ".join(web["healthcheck"]["test"]))
        self.assertIn("/healthz", " ".join(web["healthcheck"]["test"]))
        # A GI solver first, and pages bounded.
        self.assertNotEqual(flag(command, "--solvers").split(",")[0], "direct")
        self.assertEqual(flag(command, "--page-params"), "none")
        self.assertTrue(web["read_only"])
        self.assertEqual(web["cap_drop"], ["ALL"])

    def test_dockerfile_serves_tls_with_tokens_by_default(self):
        with open(os.path.join(ROOT, "deploy", "Dockerfile")) as f:
            text = f.read()
        cmd = yaml.safe_load(re.search(r"^CMD (\[.*?\])$", text, re.S | re.M).group(1)
                             .replace("\\\n", " "))
        self.assertEqual(flag(cmd, "--listen"), "0.0.0.0:50051")
        self.assertEqual(flag(cmd, "--tls-cert"), "/etc/gistream/tls/tls.crt")
        self.assertEqual(flag(cmd, "--auth-tokens"), "/etc/gistream/tokens/tokens")
        self.assertRegex(text, r"(?m)^USER 65534")
        with open(os.path.join(ROOT, ".dockerignore")) as f:
            ignored = f.read().split()
        self.assertIn("build", ignored)


if __name__ == "__main__":
    unittest.main()
