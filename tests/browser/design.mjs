// Drives the design page (`shapegen design serve`) in headless Chromium as a
// user would: draw a batch, score it with the mouse and keyboard, ask for the
// current pdf, check that predictions appear, reload and check that the page
// comes back the same, open a model's larger view. Prints one JSON line;
// exits non-zero on any failure. Run by tests/design.rs.
//
//   node design.mjs URL SCREENSHOT_DIR
import { chromium } from "playwright-core";

const [url, shots] = process.argv.slice(2);
let current = "start";
const step = (name) => { current = name; };
let page;
const shot = async (options) => { await page.evaluate(() => window.scrollTo(0, 0)); await page.screenshot(options); };
const fail = (message) => { console.error("FAIL at " + current + ": " + message); process.exit(1); };
process.on("unhandledRejection", (e) => fail(String(e)));
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
try {
  page = await browser.newPage({ viewport: { width: 1280, height: 960 } });
  // Generous: CI machines are slow, and other tests run beside this one.
  page.setDefaultTimeout(120000);
  page.on("pageerror", (e) => fail("page error: " + e.message));
  step("open the page");
  await page.goto(url);
  await page.waitForSelector("#title:has-text('spaceship')");
  if (await page.locator(".card").count() !== 0) fail("a new session shows models");
  await shot({ path: shots + "/1-empty.png" });

  step("first batch");
  // A first batch from the default pdf.
  await page.click("#next");
  await page.waitForFunction(() => document.querySelectorAll(".card img").length === 24
    && [...document.querySelectorAll(".card img")].every((i) => i.complete && i.naturalWidth > 0), null, { timeout: 20000 })
    .catch(async (e) => {
      const imgs = await page.$$eval(".card img", (is) => is.map((i) => [i.src, i.complete, i.naturalWidth]));
      fail(String(e) + " " + JSON.stringify(imgs.filter((i) => !i[2])));
    });
  await shot({ path: shots + "/2-batch.png" });

  // Score as a user who wants one or two wing pairs: look at each model's
  // parameters (its genes), select the liked ones, press 8 and Enter; then
  // the others, 0 and Enter.
  step("score the batch");
  const ids = await page.$$eval(".card", (cards) => cards.map((c) => Number(c.dataset.id)));
  const liked = [];
  for (const id of ids) {
    const model = await (await page.request.get(url + "api/model/" + id)).json();
    const wings = model.genes.filter((g) => g.node === "W").length;
    if (wings === 1 || wings === 2) liked.push(id);
  }
  if (liked.length === 0 || liked.length === ids.length) fail("the batch should hold liked and other models");
  for (const id of liked) await page.click(`.card[data-id="${id}"]`);
  await page.keyboard.press("8");
  await page.keyboard.press("Enter");
  await page.waitForSelector("#status.ok");
  for (const id of ids.filter((i) => !liked.includes(i))) await page.click(`.card[data-id="${id}"]`);
  await page.keyboard.press("0");
  await page.keyboard.press("Enter");
  await page.waitForFunction(() => [...document.querySelectorAll(".card .score")].every((s) => s.textContent.startsWith("score")));
  await shot({ path: shots + "/3-scored.png" });

  step("current pdf batch");
  // The next batch from the current pdf: the preference is fitted, and
  // every model shows its prediction and uncertainty.
  await page.selectOption("#mode", "current");
  await page.click("#next");
  await page.waitForFunction(() => document.querySelectorAll(".card .predicted").length === 24);
  await page.waitForFunction(() => [...document.querySelectorAll(".card img")].every((i) => i.complete && i.naturalWidth > 0));
  const before = await page.$$eval(".card", (cards) => cards.map((c) => c.dataset.id + " " + c.textContent));
  const predicted = await page.$$eval(".card .predicted", (p) => p.map((x) => parseFloat(x.textContent.split(" ")[1])));
  const mean = predicted.reduce((a, b) => a + b, 0) / predicted.length;
  await shot({ path: shots + "/4-current.png" });

  step("reload");
  // Reload: the same batch, scores and predictions.
  await page.reload();
  await page.waitForFunction(() => document.querySelectorAll(".card .predicted").length === 24);
  const after = await page.$$eval(".card", (cards) => cards.map((c) => c.dataset.id + " " + c.textContent));
  if (JSON.stringify(before) !== JSON.stringify(after)) fail("the page differs after a reload");
  if ((await page.inputValue("#mode")) !== "current") fail("the mode is not restored");

  step("detail");
  // A model, larger, with its parameters.
  await page.click(".card .zoom");
  await page.waitForSelector("#detail.open img");
  await page.waitForFunction(() => { const i = document.querySelector("#detail img"); return i.complete && i.naturalWidth > 0; });
  await shot({ path: shots + "/5-detail.png" });
  console.log(JSON.stringify({ ok: true, liked: liked.length, scored: ids.length, mean_predicted: mean }));
} catch (e) {
  fail(String(e));
} finally {
  await browser.close();
}
