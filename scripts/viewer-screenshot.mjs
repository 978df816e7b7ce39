// Opens a cityshade tileset page (cityshade serve) in headless Chromium with software WebGL, waits
// until every tile is drawn and takes a screenshot, coloured as exported and then (a second load,
// ?style=height) by height; there it selects a building as a click does and reads back the info
// box. Prints JSON: what was selected, the info box's text, requests that left the page's origin
// (there must be none: the page is offline). Exits 1 if the page failed.
// Usage: node scripts/viewer-screenshot.mjs URL FACADES.png HEIGHT.png
import { resolve } from "node:path";
import { createRequire } from "node:module";

const require = createRequire(resolve("node_modules") + "/");
const puppeteer = require("puppeteer-core");
const [url, facadesPng, heightPng] = process.argv.slice(2);
const WIDTH = 960, HEIGHT = 600, WAIT_MS = 400000;
const began = Date.now();

function progress(what) {
  console.error(`${((Date.now() - began) / 1000).toFixed(1)} s: ${what}`);
}

async function drawn(page) {  // every tile loaded and drawn, or the page's error
  await page.waitForFunction("window.cityshade && (window.cityshade.ready || window.cityshade.error)",
    { timeout: WAIT_MS, polling: 1000 });
  const error = await page.evaluate("window.cityshade.error");
  if (error) throw new Error(`the page failed: ${error}`);
}

async function open(browser, address, result) {
  const page = await browser.newPage();
  await page.setViewport({ width: WIDTH, height: HEIGHT });
  const origin = new URL(address).origin;
  page.on("request", (request) => {
    const where = request.url();
    if (!where.startsWith(origin) && !/^(data|blob):/.test(where)) result.offOrigin.push(where);
  });
  page.on("pageerror", (error) => result.pageErrors.push(String(error)));
  await page.goto(address, { waitUntil: "load" });
  await drawn(page);
  return page;
}

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  protocolTimeout: WAIT_MS,
  args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", `--window-size=${WIDTH},${HEIGHT}`],
});
const result = { url, offOrigin: [], pageErrors: [], selected: null, infoBox: null };
try {
  let page = await open(browser, url, result);
  await page.screenshot({ path: facadesPng });
  progress("coloured as exported: drawn");
  await page.close();
  page = await open(browser, new URL("?style=height", url).href, result);
  await page.screenshot({ path: heightPng });
  progress("coloured by height: drawn");
  result.selected = await page.evaluate("window.cityshade.selectFirst(), window.cityshade.picked");
  await page.waitForSelector(".cesium-infoBox-visible", { timeout: 60000 });
  const frame = await (await page.$(".cesium-infoBox-iframe")).contentFrame();
  await frame.waitForSelector("table", { timeout: 60000 });
  result.infoBox = await frame.$eval("table", (table) => table.innerText);
  progress(`selected ${result.selected && result.selected.source_id}`);
} catch (error) {
  result.failure = String(error);
} finally {
  await browser.close();
}
console.log(JSON.stringify(result));
process.exit(result.failure ? 1 : 0);
