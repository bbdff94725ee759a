// Drives gistream-web's viewer in Debian's headless Chromium (puppeteer-core
// with /usr/bin/chromium): the page loads, frames arrive and the canvas is
// not black, a mouse drag changes the camera (the echoed sequence number
// reaches the drag's and the picture changes), a slider changes a light
// (the picture gets brighter), the solver picker starts a new session
// that draws, a view panned off the scene says so and r brings the
// picture back, the scene picker loads another scene whose session draws;
// saves a screenshot; prints the measured
// update-to-frame latency.
//
//   node viewer_test.mjs URL OUT_DIR [jpeg|h264]
import puppeteer from "puppeteer-core";
import fs from "node:fs";
import path from "node:path";

const [url, outDir, format = "jpeg"] = process.argv.slice(2);
if (!url || !outDir) {
  console.error("usage: node viewer_test.mjs URL OUT_DIR [jpeg|h264]");
  process.exit(2);
}
fs.mkdirSync(outDir, { recursive: true });

function fail(message) {
  console.error(`FAIL (${format}): ${message}`);
  process.exitCode = 1;
  throw new Error(message);
}

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-dev-shm-usage"],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1000, height: 560 });
  page.on("console", m => console.log(`page: ${m.text()}`));
  // With VIEWER_TOKEN the gateway wants a viewer token: the page is opened
  // as /#token=..., keeps it for the tab and clears the address bar.
  const token = process.env.VIEWER_TOKEN;
  await page.goto(`${url}?format=${format}` + (token ? `#token=${encodeURIComponent(token)}` : ""),
                  { waitUntil: "load" });
  if (token && (await page.evaluate(() => location.hash)) !== "") {
    fail("the token stayed in the address bar");
  }

  const waitFor = (fn, what, arg, timeout = 120000) =>
    page.waitForFunction(fn, { timeout, polling: 50 }, arg).catch(() => fail(`timed out: ${what}`));
  // Mean of R, G, B over the canvas (0..255).
  const pixels = () => page.evaluate(() => {
    const c = document.getElementById("view");
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    let sum = 0;
    for (let i = 0; i < d.length; i += 4) sum += d[i] + d[i + 1] + d[i + 2];
    return { mean: sum / (3 * d.length / 4), data: Array.from(d.filter((_, i) => i % 16 === 0)) };
  });
  const diff = (a, b) => a.data.reduce((s, v, i) => s + Math.abs(v - b.data[i]), 0) / a.data.length;

  await waitFor(() => window.viewer && window.viewer.drawn >= 1, "first picture");
  const format_used = await page.evaluate(() => window.viewer.format);
  if (format_used !== format) fail(`the page chose ${format_used}`);
  const first = await pixels();
  if (!(first.mean > 10)) fail(`the canvas is black (mean ${first.mean.toFixed(2)})`);

  // Drag: orbit the camera.
  const box = await (await page.$("#view")).boundingBox();
  const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
  const drawnBefore = await page.evaluate(() => window.viewer.drawn);
  // The overlay's line as the frames of the drag come (the page refreshes
  // it every 250 ms): the camera move reprojects the last picture.
  await page.evaluate(() => {
    window.overlaySeen = "";
    new MutationObserver(() => {
      const t = document.getElementById("overlay").textContent;
      if (t.includes("reprojected")) window.overlaySeen = t;
    }).observe(document.getElementById("overlay"), { childList: true, subtree: true });
  });
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  for (let i = 1; i <= 8; i++) await page.mouse.move(cx + 12 * i, cy + 3 * i);
  await page.mouse.up();
  await waitFor(() => window.viewer.reprojected > 0, "a frame of the drag that reprojects");
  // What the overlay said then, if a refresh fell in those frames (a
  // screenshot of it beside the others).
  const seen = await page.waitForFunction(() => window.overlaySeen, { timeout: 3000, polling: 50 })
    .then(() => page.evaluate(() => window.overlaySeen)).catch(() => "");
  console.log(`overlay during the drag: ${seen || "(no refresh during the reprojected frames)"}`);
  if (seen) await page.screenshot({ path: path.join(outDir, `viewer_${format}_drag.png`) });
  await waitFor(() => window.viewer.seq > 0 && window.viewer.lastSeq >= window.viewer.seq,
                "the echoed sequence number reaching the drag's");
  await waitFor(d => window.viewer.drawn > d, "a picture after the drag", drawnBefore);
  await new Promise(r => setTimeout(r, 300));  // let the decode of that frame land
  const dragged = await pixels();
  const moved = diff(first, dragged);
  if (!(moved > 1)) fail(`the picture did not change after the drag (mean abs diff ${moved.toFixed(3)})`);
  const seqAfterDrag = await page.evaluate(() => window.viewer.lastSeq);

  // Slider: dim, then brighten the first light or emissive material (the
  // scene is shared, so another browser may have moved it before).
  const setSlider = value => page.evaluate(v => {
    const s = document.querySelector("#lights input, #materials input");
    if (!s) return false;
    s.value = String(v);
    s.dispatchEvent(new Event("input"));
    return true;
  }, value);
  const lightStep = async (value, after) => {
    if (!(await setSlider(value))) fail("the page shows no light or material slider");
    await waitFor(s => window.viewer.lastSeq > s, `the slider's update (${value}) in a frame`, after);
    await new Promise(r => setTimeout(r, 500));  // the decode of that frame
    return [await pixels(), await page.evaluate(() => window.viewer.lastSeq)];
  };
  const [dim, seqDim] = await lightStep(0.5, seqAfterDrag);
  const [brighter] = await lightStep(2.5, seqDim);
  if (!(brighter.mean > dim.mean + 2)) {
    fail(`the slider did not brighten the picture (${dim.mean.toFixed(2)} -> ${brighter.mean.toFixed(2)})`);
  }

  // The solver picker: new parameters start a new session, frames follow.
  const [sessions, drawn] = await page.evaluate(() => [window.viewer.sessions, window.viewer.drawn]);
  const picked = await page.evaluate(() => {
    const input = document.querySelector('#params [data-param="area_samples"]');
    if (!input) return false;
    input.value = "8";
    document.getElementById("apply").click();
    return true;
  });
  if (!picked) fail("the solver picker shows no area_samples control for direct");
  await waitFor(([s, d]) => window.viewer.sessions > s && window.viewer.drawn > d,
                "a picture from the session the picker started", [sessions, drawn]);

  await page.screenshot({ path: path.join(outDir, `viewer_${format}.png`) });

  // A view that sees nothing says why (issue 31): pan far off the scene, the
  // overlay names it; r returns to the scene's camera and the picture.
  await page.keyboard.down("Shift");
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  for (let i = 1; i <= 20; i++) await page.mouse.move(cx - 150 * i, cy);
  await page.mouse.up();
  await page.keyboard.up("Shift");
  await waitFor(() => window.viewer.black &&
                      document.getElementById("overlay").textContent.includes("nothing lit in view"),
                "the hint for a view that shows nothing");
  await page.keyboard.press("r");
  await waitFor(() => !window.viewer.black &&
                      !document.getElementById("overlay").textContent.includes("nothing lit"),
                "the picture back after r");

  // The scene picker: another bundled scene loads and a new session shows it.
  const [sessions2, drawn2, scene0] = await page.evaluate(
    () => [window.viewer.sessions, window.viewer.drawn, window.viewer.scene.scene_id]);
  const switched = await page.evaluate(() => {
    const select = document.getElementById("scene");
    if (![...select.options].some(o => o.value === "indirect_room")) return false;
    select.value = "indirect_room";
    select.dispatchEvent(new Event("change"));
    return true;
  });
  if (!switched) fail("the scene picker offers no indirect_room");
  await waitFor(([s, d, id]) => window.viewer.sessions > s && window.viewer.drawn > d &&
                                window.viewer.scene.scene_id !== id,
                "a picture of the scene the picker loaded", [sessions2, drawn2, scene0]);
  const stats = await page.evaluate(() => ({
    frames: window.viewer.frames, images: window.viewer.images, latencies: window.viewer.latencies,
    errors: window.viewer.errors, breakdown: window.viewer.breakdown,
    overlay: document.getElementById("overlay").textContent }));
  // The overlay breaks the update-to-picture time down; its parts add up.
  const b = stats.breakdown;
  if (!b) fail("no update-to-picture breakdown after the updates");
  if (!(Math.abs(b.server + b.transit + b.decode - b.total) <= 1 + 1e-6 * b.total || b.transit === 0))
    fail(`the breakdown does not add up: ${JSON.stringify(b)}`);
  if (!stats.overlay.includes("update→picture")) fail("the overlay shows no breakdown");
  const lat = [...stats.latencies].sort((a, b) => a - b);
  console.log(`PASS (${format}): ${stats.frames} frames (${stats.images} with a picture), ` +
              `update-to-frame latency median ${lat[lat.length >> 1].toFixed(0)} ms over ${lat.length} updates, ` +
              `canvas mean ${first.mean.toFixed(1)}, drag diff ${moved.toFixed(1)}, slider ${dim.mean.toFixed(1)} -> ${brighter.mean.toFixed(1)}, ` +
              `last update ${b.total.toFixed(0)} ms = server ${b.server.toFixed(0)} (encode ${b.encode.toFixed(0)}) + ` +
              `send+queue ${b.transit.toFixed(0)} + decode+draw ${b.decode.toFixed(0)}` +
              (stats.errors.length ? `, errors: ${stats.errors.join("; ")}` : ""));
} catch (e) {
  if (!process.exitCode) { console.error(`FAIL (${format}): ${e.message}`); process.exitCode = 1; }
} finally {
  await browser.close();
}
