// The tinbase service's HTTP API as the viewer uses it (docs/api.md). Every error answer is
// {"error": {status, code, message}}; these helpers throw an ApiError carrying it.

export class ApiError extends Error {
  constructor(status, code, message) {
    super(message);
    this.status = status;
    this.code = code;
  }
}

async function errorOf(response) {
  try {
    const body = await response.json();
    if (body && body.error) {
      return new ApiError(response.status, body.error.code, body.error.message);
    }
  } catch (e) {
    // not JSON: fall through to the status line
  }
  return new ApiError(response.status, 'http', `${response.status} ${response.statusText}`);
}

// The path of surface `name`'s resource `rest` ("features", "locate?..."), names escaped.
export function surfacePath(name, rest) {
  return `/surfaces/${encodeURIComponent(name)}/${rest}`;
}

// GET `path` as JSON; throws ApiError on an error answer.
export async function getJson(path) {
  const response = await fetch(path, { headers: { Accept: 'application/json' } });
  if (!response.ok) throw await errorOf(response);
  return response.json();
}

// GET `path` as a Blob with the answer's headers; throws ApiError on an error answer.
export async function getBlob(path) {
  const response = await fetch(path);
  if (!response.ok) throw await errorOf(response);
  return { blob: await response.blob(), headers: response.headers };
}

// POST `body` (JSON) to `path` with a bearer token when one is given; the answer's JSON.
export async function postJson(path, body, token, contentType = 'application/json') {
  const headers = { 'Content-Type': contentType, Accept: 'application/json' };
  if (token) headers.Authorization = `Bearer ${token}`;
  const response = await fetch(path, { method: 'POST', headers, body: JSON.stringify(body) });
  if (!response.ok) throw await errorOf(response);
  return response.json();
}

// "w,s,e,n" (a header such as X-Tinbase-Bbox-Lonlat) as four numbers, or null.
export function parseNumbers(text, count) {
  if (!text) return null;
  const values = text.split(',').map(Number);
  return values.length === count && values.every(Number.isFinite) ? values : null;
}
