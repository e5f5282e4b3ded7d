/* display.c - see display.h.  Keys: W/S or Up/Down move, A/D strafe,
 * Left/Right turn, R/F up/down (Shift: faster), +/- or the wheel zoom, a
 * left drag looks around, a right or middle drag orbits (with Shift,
 * pans), V captures the pointer for mouse look (Esc lets
 * it go), C frames the whole scene, Home resets the camera, K prints the
 * view as a scene's camera line (and puts it on the clipboard), Space toggles
 * the model animation, P saves a screenshot, Tab shows the panel, T /
 * Shift+T the frame-rate target, N the still quality, L the light
 * sampling, M the shading, H the shadows, F11 fills the screen; Esc or Q
 * quits.  A file dropped on the window is opened (window.h).  The window can be resized: a frame is drawn as large as it
 * fits, its shape kept (bars beside it), the panel at its own size (the
 * frames of another size follow, unless --fixed-size: window.c).  A
 * frame larger than the screen opens a window that fits it.  The panel's
 * text is drawn by SDL2_ttf in DejaVu Sans Mono (fonts-dejavu-core), or
 * the font LANRAY_FONT names. */
#include "display.h"

#include <SDL2/SDL.h>
#include <SDL2/SDL_ttf.h>
#include <stdlib.h>
#include <string.h>

#define DISPLAY_FONT "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
#define DISPLAY_FONT_PT 12
#define LOOK_DEG_PX 0.15 /* mouse look: degrees a pixel */
#define ORBIT_DEG_PX 0.4 /* an orbit: degrees a pixel (a drag across a 900-pixel window goes once round) */

struct Display {
    SDL_Window *win;
    SDL_Renderer *ren;
    SDL_Texture *tex;
    SDL_Texture *panel; /* the panel's lines on a translucent box, made by display_panel */
    SDL_Rect panel_at;
    TTF_Font *font;
    int ttf; /* TTF_Init done */
    int captured;
    int w, h;
    uint8_t *rgb; /* the frame shown, with the lines shown since (display_lines) */
    int pending;  /* lines shown in the texture, not yet on the screen */
    uint32_t presented_ms;
};

int display_available(void)
{
    const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    return (x && *x) || (wl && *wl);
}

/* A window of w x h shrunk, its shape kept, to fit the screen's usable
 * part (less a title bar's height): a 4K frame on a smaller screen. */
static void fit_screen(int *w, int *h)
{
    SDL_Rect r;
    if (SDL_GetDisplayUsableBounds(0, &r) != 0 || r.w <= 0 || r.h <= 64)
        return;
    const int64_t fw = *w, fh = *h, sw = r.w, sh = r.h - 48;
    if (fw <= sw && fh <= sh)
        return;
    if (fw * sh <= fh * sw) /* the height bounds it */
        *h = (int)sh, *w = (int)((fw * sh + fh / 2) / fh);
    else
        *w = (int)sw, *h = (int)((fh * sw + fw / 2) / fw);
    *w = *w > 1 ? *w : 1, *h = *h > 1 ? *h : 1;
}

Display *display_open(int w, int h, Err *err)
{
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        err_set(err, "SDL: %s", SDL_GetError());
        return NULL;
    }
    Display *d = calloc(1, sizeof *d);
    if (!d) {
        SDL_Quit();
        err_set(err, "out of memory");
        return NULL;
    }
    d->w = w;
    d->h = h;
    d->rgb = calloc((size_t)w * h, 3);
    int ww = w, wh = h;
    fit_screen(&ww, &wh);
    d->win = SDL_CreateWindow("lanray", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, ww, wh, SDL_WINDOW_RESIZABLE);
    d->ren = d->win ? SDL_CreateRenderer(d->win, -1, SDL_RENDERER_SOFTWARE) : NULL;
    d->tex = d->ren ? SDL_CreateTexture(d->ren, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, w, h) : NULL;
    if (d->tex) /* a frame drawn smaller or larger than it is: filtered, not every other pixel */
        SDL_SetTextureScaleMode(d->tex, SDL_ScaleModeLinear);
    if (!d->tex || !d->rgb) {
        if (d->rgb)
            err_set(err, "SDL: %s", SDL_GetError());
        else
            err_set(err, "out of memory for the window's %dx%d frame", w, h);
        display_close(d);
        return NULL;
    }
    SDL_SetRenderDrawColor(d->ren, 0, 0, 0, 255);
    SDL_RenderClear(d->ren);
    SDL_RenderPresent(d->ren);
    return d;
}

void display_close(Display *d)
{
    if (!d)
        return;
    if (d->panel)
        SDL_DestroyTexture(d->panel);
    if (d->font)
        TTF_CloseFont(d->font);
    if (d->ttf)
        TTF_Quit();
    if (d->tex)
        SDL_DestroyTexture(d->tex);
    if (d->ren)
        SDL_DestroyRenderer(d->ren);
    if (d->win)
        SDL_DestroyWindow(d->win);
    free(d->rgb);
    free(d);
    SDL_Quit();
}

/* Where the frame goes in the window: as large as it fits, its shape
 * kept, centred (the whole window at the frame's own size). */
static SDL_Rect frame_rect(const Display *d)
{
    int ow = d->w, oh = d->h;
    SDL_GetRendererOutputSize(d->ren, &ow, &oh);
    if (ow == d->w && oh == d->h)
        return (SDL_Rect){0, 0, d->w, d->h};
    /* the scale the narrower way bounds, in whole pixels */
    int fw = ow, fh = (int)((int64_t)ow * d->h / d->w);
    if (fh > oh)
        fh = oh, fw = (int)((int64_t)oh * d->w / d->h);
    fw = fw > 1 ? fw : 1, fh = fh > 1 ? fh : 1;
    return (SDL_Rect){(ow - fw) / 2, (oh - fh) / 2, fw, fh};
}

/* The last frame and the panel over it (at its own size, at the frame's
 * corner), to the screen. */
static void present(Display *d)
{
    SDL_RenderClear(d->ren);
    const SDL_Rect at = frame_rect(d);
    SDL_RenderCopy(d->ren, d->tex, NULL, &at);
    if (d->panel) {
        const SDL_Rect p = {at.x + d->panel_at.x, at.y + d->panel_at.y, d->panel_at.w, d->panel_at.h};
        SDL_RenderCopy(d->ren, d->panel, NULL, &p);
    }
    SDL_RenderPresent(d->ren);
    d->pending = 0;
    d->presented_ms = SDL_GetTicks();
}

/* The frame's texture and copy made again for frames of w x h (the
 * window's size followed); 0, or -1 where that failed (the old ones kept). */
static int remake(Display *d, int w, int h)
{
    uint8_t *rgb = calloc((size_t)w * h, 3);
    SDL_Texture *tex = rgb ? SDL_CreateTexture(d->ren, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, w, h) : NULL;
    if (!tex) {
        free(rgb);
        return -1;
    }
    SDL_SetTextureScaleMode(tex, SDL_ScaleModeLinear);
    SDL_DestroyTexture(d->tex);
    free(d->rgb);
    d->tex = tex, d->rgb = rgb, d->w = w, d->h = h;
    return 0;
}

void display_show(Display *d, const uint8_t *rgb, int w, int h)
{
    if ((w != d->w || h != d->h) && remake(d, w, h))
        return; /* no memory for it: the frame before stays */
    memcpy(d->rgb, rgb, (size_t)d->w * d->h * 3);
    SDL_UpdateTexture(d->tex, NULL, rgb, d->w * 3);
    present(d);
}

/* Lines come as fast as segments do (a farm's many): the screen takes them
 * at most this often, the rest at the next display_flush. */
#define DISPLAY_LINES_MS 100

void display_lines(Display *d, uint32_t first, uint32_t count, const uint8_t *rgb)
{
    const uint64_t n = (uint64_t)d->w * d->h;
    if (first >= n || count == 0)
        return;
    if (count > n - first)
        count = (uint32_t)(n - first);
    memcpy(d->rgb + (size_t)first * 3, rgb, (size_t)count * 3);
    /* the texture's rows that the pixels touch, whole */
    const int y0 = (int)(first / (uint32_t)d->w), y1 = (int)((first + count - 1) / (uint32_t)d->w);
    const SDL_Rect rows = {0, y0, d->w, y1 - y0 + 1};
    SDL_UpdateTexture(d->tex, &rows, d->rgb + (size_t)y0 * d->w * 3, d->w * 3);
    d->pending = 1;
    display_flush(d);
}

void display_flush(Display *d)
{
    if (d->pending && SDL_GetTicks() - d->presented_ms >= DISPLAY_LINES_MS)
        present(d);
}

static int open_font(Display *d, Err *err)
{
    if (d->font)
        return 0;
    if (!d->ttf) {
        if (TTF_Init() != 0)
            return err_set(err, "SDL_ttf: %s", TTF_GetError());
        d->ttf = 1;
    }
    const char *path = getenv("LANRAY_FONT");
    if (!path || !*path)
        path = DISPLAY_FONT;
    if (!(d->font = TTF_OpenFont(path, DISPLAY_FONT_PT)))
        return err_set(err, "no panel: font %s: %s (make deps installs fonts-dejavu-core)", path, TTF_GetError());
    return 0;
}

int display_panel(Display *d, char (*lines)[100], int n, Err *err)
{
    if (d->panel) {
        SDL_DestroyTexture(d->panel);
        d->panel = NULL;
    }
    if (n == 0) {
        present(d);
        return 0;
    }
    if (open_font(d, err))
        return -1;
    const int pad = 6, step = TTF_FontLineSkip(d->font);
    int width = 0;
    for (int i = 0; i < n; i++) {
        int tw = 0, th = 0;
        TTF_SizeUTF8(d->font, lines[i], &tw, &th);
        width = tw > width ? tw : width;
    }
    /* the text on a translucent dark box, made once per change of text */
    SDL_Surface *box = SDL_CreateRGBSurfaceWithFormat(0, width + 2 * pad, n * step + 2 * pad, 32, SDL_PIXELFORMAT_ARGB8888);
    if (!box)
        return err_set(err, "SDL: %s", SDL_GetError());
    SDL_FillRect(box, NULL, SDL_MapRGBA(box->format, 0, 0, 0, 170));
    for (int i = 0; i < n; i++) {
        SDL_Surface *t = TTF_RenderUTF8_Blended(d->font, lines[i][0] ? lines[i] : " ", (SDL_Color){235, 235, 235, 255});
        if (!t)
            continue;
        SDL_Rect at = {pad, pad + i * step, t->w, t->h};
        SDL_SetSurfaceBlendMode(t, SDL_BLENDMODE_BLEND);
        SDL_BlitSurface(t, NULL, box, &at);
        SDL_FreeSurface(t);
    }
    d->panel = SDL_CreateTextureFromSurface(d->ren, box);
    d->panel_at = (SDL_Rect){8, 8, box->w, box->h};
    SDL_FreeSurface(box);
    if (!d->panel)
        return err_set(err, "SDL: %s", SDL_GetError());
    SDL_SetTextureBlendMode(d->panel, SDL_BLENDMODE_BLEND);
    present(d);
    return 0;
}

void display_title(Display *d, const char *title) { SDL_SetWindowTitle(d->win, title); }

int display_clipboard(Display *d, const char *text)
{
    (void)d;
    return SDL_SetClipboardText(text) == 0 ? 0 : -1;
}

void display_set_size(Display *d, int w, int h)
{
    fit_screen(&w, &h);
    SDL_SetWindowSize(d->win, w, h);
}

int display_drawn_width(Display *d) { return frame_rect(d).w; }

void display_output_size(Display *d, int *w, int *h)
{
    if (SDL_GetRendererOutputSize(d->ren, w, h) != 0 || *w < 1 || *h < 1)
        *w = d->w, *h = d->h;
}

static void capture(Display *d, int on)
{
    d->captured = on && SDL_SetRelativeMouseMode(SDL_TRUE) == 0;
    if (!on)
        SDL_SetRelativeMouseMode(SDL_FALSE);
}

static void key_down(Display *d, const SDL_KeyboardEvent *k, DisplayInput *in)
{
    const int shift = (k->keysym.mod & KMOD_SHIFT) != 0;
    switch (k->keysym.sym) {
    case SDLK_ESCAPE: /* lets the pointer go first */
        if (d->captured)
            capture(d, 0);
        else
            in->quit = 1;
        break;
    case SDLK_q: in->quit = 1; break;
    case SDLK_p: in->screenshot = 1; break;
    case SDLK_HOME: in->reset = 1; break;
    case SDLK_SPACE: in->toggle_animation = 1; break;
    case SDLK_PLUS:
    case SDLK_EQUALS:
    case SDLK_KP_PLUS: in->zoom += 1; break;
    case SDLK_MINUS:
    case SDLK_KP_MINUS: in->zoom -= 1; break;
    case SDLK_TAB: in->toggle_panel = 1; break;
    case SDLK_c: in->frame_all = 1; break;
    case SDLK_k: in->print_view = 1; break;
    case SDLK_v: capture(d, !d->captured); break;
    case SDLK_t: *(shift ? &in->target_down : &in->target_up) = 1; break;
    case SDLK_n: in->next_still = 1; break;
    case SDLK_l: in->toggle_lights = 1; break;
    case SDLK_m: in->toggle_shading = 1; break;
    case SDLK_h: in->toggle_shadows = 1; break;
    case SDLK_u: in->toggle_upscale = 1; break;
    case SDLK_x: in->toggle_denoise = 1; break;
    case SDLK_F11: { /* the screen filled, or the window back */
        const Uint32 full = SDL_WINDOW_FULLSCREEN_DESKTOP;
        SDL_SetWindowFullscreen(d->win, (SDL_GetWindowFlags(d->win) & full) == full ? 0 : full);
        break;
    }
    default: break;
    }
}

void display_poll(Display *d, DisplayInput *in)
{
    memset(in, 0, sizeof *in);
    SDL_Event e;
    while (SDL_PollEvent(&e)) {
        switch (e.type) {
        case SDL_QUIT: in->quit = 1; break;
        case SDL_WINDOWEVENT: /* shown again or resized: the last frame, drawn again (an idle window gets no new one) */
            if (e.window.event == SDL_WINDOWEVENT_EXPOSED || e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED)
                present(d);
            else if (e.window.event == SDL_WINDOWEVENT_FOCUS_LOST && d->captured)
                capture(d, 0);
            break;
        case SDL_MOUSEMOTION:
            if (d->captured || (e.motion.state & SDL_BUTTON_LMASK)) {
                in->yaw -= e.motion.xrel * LOOK_DEG_PX;
                in->pitch -= e.motion.yrel * LOOK_DEG_PX;
            } else if ((e.motion.state & (SDL_BUTTON_RMASK | SDL_BUTTON_MMASK)) && (SDL_GetModState() & KMOD_SHIFT)) {
                in->pan_x += e.motion.xrel;
                in->pan_y += e.motion.yrel;
            } else if (e.motion.state & (SDL_BUTTON_RMASK | SDL_BUTTON_MMASK)) {
                in->orbit_yaw -= e.motion.xrel * ORBIT_DEG_PX;
                in->orbit_pitch -= e.motion.yrel * ORBIT_DEG_PX;
            }
            break;
        case SDL_MOUSEWHEEL: in->zoom += e.wheel.y; break;
        case SDL_DROPFILE: /* a path longer than the room is not opened cut short */
            if (e.drop.file && strlen(e.drop.file) < sizeof in->dropped)
                strcpy(in->dropped, e.drop.file);
            SDL_free(e.drop.file);
            break;
        case SDL_KEYDOWN:
            if (!e.key.repeat)
                key_down(d, &e.key, in);
            break;
        default: break;
        }
    }
    const Uint8 *k = SDL_GetKeyboardState(NULL);
    in->forward = (k[SDL_SCANCODE_W] || k[SDL_SCANCODE_UP]) - (k[SDL_SCANCODE_S] || k[SDL_SCANCODE_DOWN]);
    in->right = k[SDL_SCANCODE_D] - k[SDL_SCANCODE_A];
    in->up = k[SDL_SCANCODE_R] - k[SDL_SCANCODE_F];
    in->turn = k[SDL_SCANCODE_LEFT] - k[SDL_SCANCODE_RIGHT];
    in->fast = k[SDL_SCANCODE_LSHIFT] || k[SDL_SCANCODE_RSHIFT];
}
