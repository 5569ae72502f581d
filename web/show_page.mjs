// Opens a report page in Debian's headless Chromium (through Playwright's
// core, no browser of its own) and waits until every view shows its model.
// Prints {"seconds": s, "views": n}: from the start of the page's load to
// its last view ready. With a second argument, a screenshot there.
//   node web/show_page.mjs CHROMIUM REPORT.html [SHOT.png]
import { chromium } from 'playwright-core';
import { resolve } from 'node:path';

const [executablePath, file, screenshot] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 1100 } });
  const start = Date.now();
  await page.goto('file://' + resolve(file));
  const views = await page.evaluate(() => document.querySelectorAll('canvas').length);
  if (views === 0) throw new Error(file + ': the page has no views');
  await page.waitForFunction((n) => Number(document.body.dataset.loaded || 0) >= n, views, { timeout: 120000 });
  const seconds = (Date.now() - start) / 1000;
  // Two frames more: the views draw what they loaded.
  await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
  if (screenshot) await page.screenshot({ path: screenshot });
  console.log(JSON.stringify({ seconds, views }));
} finally {
  await browser.close();
}
