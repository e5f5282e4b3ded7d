/* display.c - see display.h.  Keys: W/S or Up/Down move, A/D strafe, Left/Right
 * turn, R/F up/down, +/- or the wheel zoom, mouse drag looks around, Space
 * toggles the model animation, P saves a screenshot, Home resets the camera,
 * Esc or Q quits. */
#include "display.h"

#include <SDL2/SDL.h>
#include <stdlib.h>
#include <string.h>

struct Display {
    SDL_Window *win;
    SDL_Renderer *ren;
    SDL_Texture *tex;
    int w, h;
};

int display_available(void)
{
    const char *x = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    return (x && *x) || (wl && *wl);
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
    d->win = SDL_CreateWindow("lanray", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, w, h, 0);
    d->ren = d->win ? SDL_CreateRenderer(d->win, -1, SDL_RENDERER_SOFTWARE) : NULL;
    d->tex = d->ren ? SDL_CreateTexture(d->ren, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, w, h) : NULL;
    if (!d->tex) {
        err_set(err, "SDL: %s", SDL_GetError());
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
    if (d->tex)
        SDL_DestroyTexture(d->tex);
    if (d->ren)
        SDL_DestroyRenderer(d->ren);
    if (d->win)
        SDL_DestroyWindow(d->win);
    free(d);
    SDL_Quit();
}

void display_show(Display *d, const uint8_t *rgb)
{
    SDL_UpdateTexture(d->tex, NULL, rgb, d->w * 3);
    SDL_RenderClear(d->ren);
    SDL_RenderCopy(d->ren, d->tex, NULL, NULL);
    SDL_RenderPresent(d->ren);
}

void display_title(Display *d, const char *title) { SDL_SetWindowTitle(d->win, title); }

void display_poll(Display *d, DisplayInput *in)
{
    memset(in, 0, sizeof *in);
    SDL_Event e;
    while (SDL_PollEvent(&e)) {
        switch (e.type) {
        case SDL_QUIT: in->quit = 1; break;
        case SDL_WINDOWEVENT: /* shown again: the last frame, drawn again (an idle window gets no new one) */
            if (e.window.event == SDL_WINDOWEVENT_EXPOSED) {
                SDL_RenderClear(d->ren);
                SDL_RenderCopy(d->ren, d->tex, NULL, NULL);
                SDL_RenderPresent(d->ren);
            }
            break;
        case SDL_MOUSEMOTION:
            if (e.motion.state & SDL_BUTTON_LMASK) {
                in->yaw -= e.motion.xrel * 0.2;
                in->pitch -= e.motion.yrel * 0.2;
            }
            break;
        case SDL_MOUSEWHEEL: in->zoom += e.wheel.y; break;
        case SDL_KEYDOWN:
            switch (e.key.keysym.sym) {
            case SDLK_ESCAPE:
            case SDLK_q: in->quit = 1; break;
            case SDLK_p: in->screenshot = 1; break;
            case SDLK_HOME: in->reset = 1; break;
            case SDLK_SPACE: in->toggle_animation = 1; break;
            case SDLK_PLUS:
            case SDLK_EQUALS:
            case SDLK_KP_PLUS: in->zoom += 1; break;
            case SDLK_MINUS:
            case SDLK_KP_MINUS: in->zoom -= 1; break;
            default: break;
            }
            break;
        default: break;
        }
    }
    const Uint8 *k = SDL_GetKeyboardState(NULL);
    in->forward += (k[SDL_SCANCODE_W] || k[SDL_SCANCODE_UP]) - (k[SDL_SCANCODE_S] || k[SDL_SCANCODE_DOWN]);
    in->right += k[SDL_SCANCODE_D] - k[SDL_SCANCODE_A];
    in->up += k[SDL_SCANCODE_R] - k[SDL_SCANCODE_F];
    in->yaw += 2.0 * (k[SDL_SCANCODE_LEFT] - k[SDL_SCANCODE_RIGHT]);
}
